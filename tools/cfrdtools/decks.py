"""Fixed-format deck fields (docs/cards.md): I5 integers, F10 reals, A10 text, free reals."""

import math

REAL_RTOL = 1.0e-7      # relative accuracy a fixed F10 field must keep


class FieldOverflow(ValueError):
    """A value that cannot be written into its fixed-width field accurately enough."""


def fmt_int(value, width=5):
    """Right-justified integer field (I5); raises FieldOverflow if it does not fit."""
    text = str(int(value))
    if len(text) > width:
        raise FieldOverflow(f"integer {value} does not fit in an I{width} field")
    return text.rjust(width)


def _compact_e(value, decimals):
    """'1.234567E-5' style: no '+' and no leading zeros in the exponent."""
    mant, exp = f"{value:.{decimals}e}".split("e")
    return f"{mant}E{int(exp)}"


def real_candidates(value, width=10):
    """Every F and compact-E spelling of value that fits in width columns.

    The F spelling drops a leading zero ('.0075679160', '-.5') to gain a digit; a whole
    number may go without its point when the point would not fit.
    """
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
        text = _compact_e(value, dec)
        if len(text) <= width:
            out.append(text)
            break
    return out


def fmt_real(value, width=10, rtol=REAL_RTOL):
    """Right-justified real field (F10.0) holding value to relative accuracy rtol.

    The shortest spelling that is exact up to floating-point noise (1e-12) is taken when
    one fits, so decks stay readable ('255.2', not '255.200000'); otherwise the most
    accurate F or compact-E spelling that fits. Raises FieldOverflow when none keeps rtol
    (e.g. 1.23456789e-300 in 10 columns).
    """
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
    best = None
    for text in real_candidates(value, width):
        err = abs(float(text) - value)
        if best is None or err < best[0]:
            best = (err, text)
    if best is None or best[0] > rtol * abs(value):
        shown = best[1] if best else "nothing"
        raise FieldOverflow(
            f"real {value!r} cannot be written in {width} columns to {rtol:g} relative "
            f"accuracy (best: '{shown}')")
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
