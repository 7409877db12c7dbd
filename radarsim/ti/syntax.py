"""One CLI line of a TI profile: its number conversions and its error messages.

Units follow TI on the file side (GHz, us, MHz/us, ksps, ms, dB) and SI in `RadarConfig`; every
value is converted exactly once, through its decimal text (``"18.81"`` us becomes the float
nearest to 18.81e-6 s), so a write/read cycle is bit-exact (`fmt_decimal` is the inverse).
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import Any

from core.errors import BadInput

__all__ = ["Line", "LineError", "fmt_decimal", "channel_bits", "as_tuples", "DIRECTIVE_RE",
           "COMMENT_START", "is_comment", "code_part"]

#: A ``% radarsim: field = value`` directive comment.
DIRECTIVE_RE = re.compile(r"^%\s*radarsim\s*:\s*(\w+)\s*=\s*(.*?)\s*$")
#: First characters of a comment line, or of a trailing note after a command's arguments, in
#: a TI CLI profile (TI's own files use ``%``; users' files also ``#``).
COMMENT_START = "%#"


def is_comment(stripped: str) -> bool:
    """Whether a stripped, non-empty line is a comment (or a ``% radarsim:`` directive)."""
    return stripped[:1] in COMMENT_START


def code_part(line: str) -> str:
    """The part of a line that is read: "" for a comment line, else its tokens before the
    first one that starts a trailing note, joined by single spaces."""
    tokens = line.split()
    if not tokens or is_comment(tokens[0]):
        return ""
    cut = next((i for i, t in enumerate(tokens) if t[:1] in COMMENT_START), len(tokens))
    return " ".join(tokens[:cut])


def fmt_decimal(value: float | int | Decimal, exponent: int = 0) -> str:
    """Decimal text t with float(Decimal(t) x 10^exponent) == value exactly (shortest repr)."""
    d = value if isinstance(value, Decimal) else Decimal(repr(float(value)))
    d = d.scaleb(-exponent).normalize()
    text = format(d, "f")
    return "0" if text in ("-0", "0") else text


class LineError(BadInput):
    """A profile error, its message prefixed by "line N (command):"."""


@dataclass(frozen=True, slots=True)
class Line:
    no: int
    cmd: str
    args: tuple[str, ...]

    def fail(self, message: str) -> ValueError:
        return LineError(f"line {self.no} ({self.cmd}): {message}")

    def dec(self, i: int, name: str) -> Decimal:
        tok = self.args[i]
        try:
            d = Decimal(tok)
        except InvalidOperation:
            raise self.fail(f"{name}={tok!r} is not a number") from None
        if not d.is_finite():
            raise self.fail(f"{name}={tok!r} must be finite")
        return d

    def si(self, i: int, name: str, exponent: int) -> float:
        # Through the decimal text, so "18.81" us is exactly the float nearest 18.81e-6 s.
        return float(self.dec(i, name).scaleb(exponent))

    def int(self, i: int, name: str, lo: int | None = None, hi: int | None = None,
            chip: str | None = None) -> int:
        tok = self.args[i]
        # TI's CLI reads integers with atoi: "2950.00" (TI toolbox profiles) is 2950; a
        # fractional value is refused rather than truncated.
        if not re.fullmatch(r"[+-]?\d+(\.0*)?|0[xX][0-9a-fA-F]+", tok):
            raise self.fail(f"{name}={tok!r} is not an integer")
        val = int(tok, 0) if tok.lower().startswith("0x") else int(tok.split(".")[0])
        if (lo is not None and val < lo) or (hi is not None and val > hi):
            rng = f"{lo if lo is not None else '-inf'}..{hi if hi is not None else 'inf'}"
            raise self.fail(f"{name}={val} is outside {rng}" +
                            (f" ({chip} limit)" if chip else ""))
        return val

    def flag(self, i: int, name: str) -> bool:
        return bool(self.int(i, name, 0, 1))


def channel_bits(mask: int) -> tuple[int, ...]:
    """1-based channel numbers of the set bits of a TI channel mask."""
    return tuple(i + 1 for i in range(mask.bit_length()) if mask >> i & 1)


def as_tuples(v: Any) -> Any:
    """JSON lists as (nested) tuples, the form `RadarConfig` fields hold."""
    return tuple(as_tuples(x) for x in v) if isinstance(v, list) else v
