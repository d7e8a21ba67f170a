"""Deck cards (docs/cards.md): fixed I5, F10 and A10 fields, free '&' cards, and a reader of
the groups of a fixed-format deck."""

import math

REAL_RTOL = 1.0e-7      # relative accuracy a fixed F10 field must keep
GROUPS = ("TITLE", "CONTROL", "NODES", "ELEMENTS", "MATERIALS", "BOUNDARY", "LOADS",
          "STAGES", "RESERVOIR", "GAUGES", "INTERFACE", "SLAB", "CONTACT", "PLINTH", "END",
          "STOP")


class FieldOverflow(ValueError):
    """A value that cannot be written into its fixed-width field accurately enough."""


def fmt_int(value, width=5):
    """Right-justified integer field (I5); raises FieldOverflow if it does not fit."""
    text = str(int(value))
    if len(text) > width:
        raise FieldOverflow(f"integer {value} does not fit in an I{width} field")
    return text.rjust(width)


def real_candidates(value, width=10):
    """The most accurate F and compact-E ('1.2E-5') spellings of value that fit in width
    columns; the F spelling drops a leading zero ('.0075679160', '-.5') to gain a digit, a
    whole number may go without its point when the point would not fit."""
    out = []
    for dec in range(width, -1, -1):
        text = f"{value:.{dec}f}"
        if text.startswith("0."):
            text = text[1:]
        elif text.startswith("-0."):
            text = "-" + text[2:]
        if dec == 0 and len(text) < width:
            text += "."
        if len(text) <= width:
            out.append(text)
            break
    for dec in range(width, -1, -1):
        mant, exp = f"{value:.{dec}e}".split("e")
        if len(text := f"{mant}E{int(exp)}") <= width:
            out.append(text)
            break
    return out


def fmt_real(value, width=10, rtol=REAL_RTOL):
    """Right-justified real field (F10.0) holding value to relative accuracy rtol: the
    shortest spelling exact up to floating-point noise (1e-12) when one fits ('255.2', not
    '255.200000'), else the most accurate that fits; FieldOverflow when none keeps rtol
    (e.g. 1.23456789e-300 in 10 columns)."""
    value = float(value)
    if not math.isfinite(value):
        raise FieldOverflow(f"{value!r} is not a finite number")
    if value == 0.0:
        return "0.0".rjust(width)
    for dec in range(1, width):
        text = f"{value:.{dec}f}"
        if len(text) > width:
            break
        if abs(float(text) - value) <= 1e-12 * abs(value):
            return text.rjust(width)
    best = min(((abs(float(t) - value), t) for t in real_candidates(value, width)),
               default=None, key=lambda b: b[0])
    if best is None or best[0] > rtol * abs(value):
        raise FieldOverflow(f"real {value!r} cannot be written in {width} columns to {rtol:g} "
                            f"relative accuracy (best: '{best[1] if best else 'nothing'}')")
    return best[1].rjust(width)


def free_real(value):
    """Full-precision spelling for the '&' free format (Python repr, upper-case E)."""
    value = float(value)
    if not math.isfinite(value):
        raise FieldOverflow(f"{value!r} is not a finite number")
    return repr(value).upper()


def fmt_alpha(text, width=10):
    text = "" if text is None else str(text)
    if len(text) > width:
        raise FieldOverflow(f"text '{text}' longer than {width} columns")
    return text.ljust(width)


def card(fields, free=False):
    """A card of (kind, value) fields, kind 'i' (I5), 'r' (F10; a string is written as it
    is) or 'a' (A10), None a blank field; trailing blanks dropped. free: '&' and the same
    fields comma-separated, reals in full precision."""
    while fields and fields[-1][1] is None:
        fields = fields[:-1]
    out = []
    for kind, val in fields:
        if free:
            if kind == "a" and "," in str(val):
                raise FieldOverflow(f"text '{val}' has a comma: not allowed in free format")
            out.append("" if val is None else str(int(val)) if kind == "i" else
                       str(val) if kind == "a" or isinstance(val, str) else free_real(val))
        elif val is None:
            out.append(" " * (5 if kind == "i" else 10))
        elif kind == "r":
            text = val if isinstance(val, str) else fmt_real(val)
            if len(text) > 10:
                raise FieldOverflow(f"'{text}' longer than 10 columns")
            out.append(text.rjust(10))
        else:
            out.append(fmt_int(val) if kind == "i" else fmt_alpha(val))
    if free:
        return "&" + ", ".join(out)
    line = "".join(out).rstrip()
    if len(line) > 80:
        raise FieldOverflow(f"card longer than 80 columns: {line!r}")
    return line


def free(*values):
    """A free-format card: '&' and the values comma-separated (reals by repr, None blank):
    free(1, None, 0.5) is '&1, , 0.5'."""
    return "&" + ", ".join("" if v is None else repr(v) if isinstance(v, float) else str(v)
                           for v in values)


EFFECTS = ("ROCKFILL", "UNLOAD", "WATER", "INTERFACE", "FRICTION", "SLIP", "PHASES")


def with_effects(text, **switch):
    """The deck text with an EFFECTS card (A10 fields after the keyword, blank = the default;
    switch: field -> value) after its CONTROL header (the group takes it anywhere)."""
    lines = text.split("\n")
    k = next(i for i, line in enumerate(lines) if line.rstrip() == "CONTROL")
    card = "EFFECTS   " + "".join(f"{switch.get(f, ''):<10s}" for f in EFFECTS)
    return "\n".join(lines[:k + 1] + [card] + lines[k + 1:])


def groups(text):
    """The data cards of a fixed-format deck by group, in order: [(GROUP, [card, ...])]
    (comment and blank cards left out; a header's own card is not among its cards)."""
    out = []
    for line in text.split("\n"):
        line = line.rstrip("\r")
        if not line.strip() or line[0] == "*":
            continue
        word = line[:10].strip().upper()
        if line[0] != " " and word in GROUPS:
            out.append((word, []))
        elif out:
            out[-1][1].append(line)
    return out


def materials(text):
    """{number: (LAW, [data cards])} of the MATERIALS group of a fixed-format deck."""
    out, number = {}, None
    for group, cards in groups(text):
        for line in cards if group == "MATERIALS" else ():
            law = line[5:15].strip().upper()
            if line[:5].strip().isdigit() and law in ("ELASTIC", "EB", "GOODMAN", "PJOINT"):
                number = int(line[:5])
                out[number] = (law, [])
            elif number is not None:
                out[number][1].append(line)
    return out


def unit_weights(text):
    """{material: unit weight}: GAMMA of an EB material (columns 1-10 of its first card) or
    an ELASTIC one (21-30); a GOODMAN or PJOINT joint weighs nothing."""
    columns = {"EB": slice(0, 10), "ELASTIC": slice(20, 30)}
    return {m: float(cards[0][columns[law]] or 0.0) if law in columns else 0.0
            for m, (law, cards) in materials(text).items()}
