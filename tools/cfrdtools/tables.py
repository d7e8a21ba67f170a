"""Tables of results: markdown rows, and aligned plain text."""


def row(cells):
    """A markdown table row ('|' inside a cell escaped)."""
    return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"


def markdown(header, rows, align=None):
    """A markdown table; align: 'l' or 'r' per column ('|:---|' or '|---:|'; None: '---')."""
    rule = "|" + "|".join("---:" if a == "r" else ":---" for a in align) + "|" if align \
        else "|" + "---|" * len(header)
    return "\n".join([row(header), rule] + [row(r) for r in rows])


def aligned(header, rows, right=()):
    """Plain text columns two blanks apart, the columns numbered in `right` right-justified,
    a rule of dashes under the header."""
    widths = [max(len(h), *(len(r[k]) for r in rows)) for k, h in enumerate(header)]

    def line(cells):
        return "  ".join(c.rjust(w) if k in right else c.ljust(w)
                         for k, (c, w) in enumerate(zip(cells, widths))).rstrip()
    return "\n".join([line(header), "  ".join("-" * w for w in widths)] + [line(r) for r in rows])
