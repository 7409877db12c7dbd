"""``compRangeBiasAndRxChanPhase``: the board calibration line of the mmWave SDK 3.x demos
(xWR16xx/18xx/68xx) and the MCU+ SDK AWR294x TDM demo, read into the processing settings
``range_bias_m`` and ``channel_comp`` (`pipeline.compensation` applies them).

Syntax (``MmwDemo_CLICompRangeBiasAndRxChanPhaseCfg``)::

    compRangeBiasAndRxChanPhase <rangeBias> <Re(0,0)> <Im(0,0)> ... <Re(T-1,R-1)> <Im(T-1,R-1)>

one (Re, Im) pair per Tx x Rx pair of the chip, Tx major in chip channel order, whatever
``channelCfg`` enables: the demo's CLI refuses any other count
(``argc != 1 + 1 + SYS_COMMON_NUM_TX_ANTENNAS * SYS_COMMON_NUM_RX_CHANNEL * 2``) and stores each
part as Q15 (``value * 32768`` saturated to int16). The radar's own virtual channels take their
pairs from that list (`pipeline.compensation.ti_pair_index`).
"""
from __future__ import annotations

from .state import ParseState
from .syntax import Line

__all__ = ["comp_range_bias_and_rx_chan_phase", "comp_value_count"]


def comp_value_count(chip) -> int:
    """Values after the command for a chip: rangeBias + Re/Im of n_tx x n_rx pairs."""
    return 1 + 2 * chip.n_tx * chip.n_rx


def comp_range_bias_and_rx_chan_phase(st: ParseState, ln: Line) -> None:
    want = comp_value_count(st.chip)
    if len(ln.args) != want:
        raise ln.fail(f"{len(ln.args)} values; the {st.chip.name} needs {want} (rangeBias, "
                      f"then Re, Im of each of its {st.chip.n_tx} Tx x {st.chip.n_rx} Rx "
                      "pairs, Tx major)")
    bias = float(ln.dec(0, "rangeBias"))
    parts = []
    for i in range(1, want):
        v = float(ln.dec(i, f"{'Re' if i % 2 else 'Im'}({(i - 1) // 2 // st.chip.n_rx},"
                            f"{(i - 1) // 2 % st.chip.n_rx})"))
        if not -1.0 <= v <= 1.0:
            raise ln.fail(f"value {i + 1} = {v:g} is outside the Q15 range [-1, 1] (the demo "
                          "would saturate it)")
        parts.append(v)
    st.processing.update(range_bias_m=bias, channel_comp=tuple(zip(parts[0::2], parts[1::2])))
    st.processing_commands[ln.cmd] = ln
