"""Which chip a TI profile was written for: a ``% radarsim: chip`` directive, TI Visualizer's
``% Platform:`` header, or the commands themselves."""
from __future__ import annotations

import json
import re

from ..boards import BOARDS
from ..chips import CHIPS
from .syntax import DIRECTIVE_RE, LineError

__all__ = ["PLATFORMS", "infer_chip", "platform_board"]


#: Family spellings of the ``% Platform:`` header other TI tools and SDK releases write.
_PLATFORM_ALIASES = {
    "awr18xx": "AWR1843", "iwr18xx": "AWR1843", "xwr1843": "AWR1843", "iwr1843": "AWR1843",
    "awr16xx": "AWR1642", "iwr16xx": "AWR1642", "xwr1642": "AWR1642", "iwr1642": "AWR1642",
    "iwr68xx": "IWR6843", "xwr64xx": "IWR6843", "awr6843": "IWR6843", "xwr6843": "IWR6843",
    "xwr294x": "AWR2944", "xwr2544": "AWR2544",
    "awr14xx": "AWR1443", "iwr14xx": "AWR1443", "xwr1443": "AWR1443", "iwr1443": "AWR1443",
    "xwr1243": "AWR1243", "iwr1243": "AWR1243", "xwr2243": "AWR2243", "iwr2243": "AWR2243",
    # mmWave Studio select_chip_version names.
    "ar1243": "AWR1243", "ar1443": "AWR1443", "ar1642": "AWR1642", "ar1843": "AWR1843",
    "ar6843": "IWR6843", "awr1243p": "AWR1243", "awr2243p": "AWR2243",
}
#: TI visualizer ``% Platform:`` names -> chip: each chip's own name and its
#: `Chip.ti_platform` (the header TI's Visualizer writes), plus the aliases.
PLATFORMS = {**{name.lower(): name for name in CHIPS},
             **{c.ti_platform.lower(): name for name, c in CHIPS.items()}, **_PLATFORM_ALIASES}
_PLATFORM_RE = re.compile(r"^%\s*platform\s*:\s*(\S+)", re.IGNORECASE)


def infer_chip(lines: list[str]) -> tuple[str, str]:
    """(chip, how it was found) from a ``% radarsim: chip`` directive, TI's ``% Platform:``
    header, or the commands: 60-64 GHz -> IWR6843; complex ADC -> AWR1443 with an interleaved
    ADC buffer (xWR14xx demo), AWR1843 with Tx3 enabled, else AWR1642; real ADC -> the
    AWR294x family (AWR2544 with ``procChainCfg``, AWR2944P with the 5-argument
    ``channelCfg``, else AWR2944)."""
    cmds: dict[str, list[str]] = {}
    for raw in lines:
        text = raw.strip()
        m = DIRECTIVE_RE.match(text)
        if m and m.group(1) == "chip":
            try:
                return str(json.loads(m.group(2))), "directive"
            except json.JSONDecodeError:
                return m.group(2).strip('"\''), "directive"
        m = _PLATFORM_RE.match(text)
        if m:
            name = m.group(1).lower()
            base = name.split("_")[0]  # xWR68xx_AOP, xWR18xx_AOP: the chip of the base name
            if name in PLATFORMS or base in PLATFORMS:
                chip = PLATFORMS.get(name, PLATFORMS.get(base))
                how = f"'% Platform:{m.group(1)}' header"
                if name not in PLATFORMS and _board_of_platform(name) is None:
                    how += (f" (the {m.group(1)} board is not in the board registry: the "
                            f"{chip}'s default board is assumed unless antGeometryCfg is given)")
                return chip, how
        if text and not text.startswith("%"):
            cmd, *args = text.split()
            cmds.setdefault(cmd, args)
    prof = cmds.get("profileCfg", [])
    try:
        start_ghz = float(prof[1])
    except (IndexError, ValueError):
        start_ghz = 77.0
    if start_ghz < 70.0:
        return "IWR6843", "start frequency in the 60-64 GHz band"
    adc = cmds.get("adcCfg", [])
    chan = cmds.get("channelCfg", [])
    buf = cmds.get("adcbufCfg", [])
    if len(adc) >= 2 and adc[1] in ("1", "2"):
        # ChanInterleave 0 (interleaved) is the xWR14xx SDK demo's only buffer mode.
        if len(buf) >= 3 and buf[-2] == "0":
            return "AWR1443", "complex ADC with an interleaved ADC buffer (xWR14xx demo)"
        tx = int(chan[1]) if len(chan) >= 2 and chan[1].isdigit() else 3
        if tx > 3:
            return "AWR1843", "complex ADC with Tx3 enabled"
        return "AWR1642", "complex ADC with Tx1/Tx2"
    if "procChainCfg" in cmds:
        return "AWR2544", "real ADC with procChainCfg (AWR2544 DDM demo)"
    if len(chan) == 5:
        return "AWR2944P", "real ADC with the 5-argument channelCfg (AWR2x44P)"
    return "AWR2944", "real ADC at 76-81 GHz"


def _board_of_platform(name: str) -> str | None:
    """The registered board whose `Board.ti_platform` is `name` (case-insensitive)."""
    for board_name in BOARDS:
        board = BOARDS[board_name]
        if board.ti_platform and board.ti_platform.lower() == name.lower():
            return board_name
    return None


def platform_board(lines: list[str], chip: str) -> str | None:
    """The board a TI Visualizer ``% Platform:`` header names (``xWR68xx_AOP`` ->
    IWR6843AOPEVM: `radarsim.boards.Board.ti_platform`), or None (the chip's default board).

    Raises
    ------
    LineError
        The header names a board that carries another chip than `chip`, the profile's (e.g.
        a ``% radarsim: chip`` directive that contradicts it).
    """
    for no, raw in enumerate(lines, 1):
        m = _PLATFORM_RE.match(raw.strip())
        if m:
            board = _board_of_platform(m.group(1))
            if board is not None and BOARDS[board].chip != chip:
                raise LineError(f"line {no}: '% Platform:{m.group(1)}' means board {board}, "
                                f"which carries a {BOARDS[board].chip}, not the profile's chip "
                                f"{chip}")
            return board
    return None
