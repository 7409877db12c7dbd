"""The frame's chirp table as a MIMO schedule: which Tx each chirp enables becomes the
scheme (`radarsim.mimo.MIMO_SCHEMES`), the Tx channels and their order."""
from __future__ import annotations

from ..mimo.schemes import MIMO_SCHEMES
from .handlers import TI_SCHEME_COMMANDS
from .parse_state import ParseState
from .syntax import Line, channel_bits

__all__ = ["frame_masks", "schedule"]


def frame_masks(st: ParseState) -> tuple[list[int], int]:
    """Tx masks of the frame's chirps (one loop) and their profile; unused chirps noted."""
    fr = st.frame
    fln: Line = fr["line"]
    masks, pids = [], set()
    for idx in range(fr["start"], fr["end"] + 1):
        if idx not in st.chirps:
            raise fln.fail(f"chirp {idx} of the frame is not defined by any chirpCfg")
        tx, pid, cln, varies = st.chirps[idx]
        if varies:
            raise cln.fail("startFreqVar/freqSlopeVar/idleTimeVar/adcStartTimeVar: per-chirp "
                           "variations are not modelled (every chirp of a RadarConfig is the "
                           "same); use 0")
        if tx == 0:
            raise cln.fail(f"txEnable=0: chirp {idx} of the frame transmits on no Tx")
        if tx & ~st.tx_mask:
            raise cln.fail(f"txEnable={tx} (0b{tx:04b}) enables a Tx that channelCfg "
                           f"txChannelEn={st.tx_mask} (0b{st.tx_mask:04b}) leaves off")
        masks.append(tx)
        pids.add(pid)
    if len(pids) > 1:
        raise fln.fail(f"the frame's chirps use profiles {sorted(pids)}: RadarConfig describes "
                       "one chirp profile")
    unused = sorted(set(st.chirps) - set(range(fr["start"], fr["end"] + 1)))
    if st.advanced:  # the other sub-frames use them
        return masks, pids.pop()
    if unused:
        st.notes.append(f"chirps {unused} are defined but not used by the frame (ignored)")
    unused_p = sorted(set(st.profiles) - pids)
    if unused_p:
        st.notes.append(f"profiles {unused_p} are not used by the frame's chirps (ignored)")
    return masks, pids.pop()


def schedule(st: ParseState, masks: list[int]) -> dict:
    """MIMO scheme, Tx channels and order from the frame's chirp Tx masks.

    The chip channels the chirps use become the logical Tx 1..n (`RadarConfig.tx_channels`);
    the registered scheme that claims the logical pattern (`radarsim.mimo.MimoScheme.from_ti`)
    gives mimo, sub-bands and order: DDMA when every chirp enables the same two or more Tx
    (without ``ddmPhaseShiftAntOrder`` the R79 demo's order, horizontal Tx first), TDMA when
    each chirp enables one Tx and the loop repeats a sequence in which each fires once."""
    fr, fln = st.frame, st.frame["line"]
    used = 0
    for m in masks:
        used |= m
    chans = channel_bits(used)
    unused = sorted(set(channel_bits(st.tx_mask)) - set(chans))
    if unused:
        st.notes.append(f"Tx {unused} enabled by channelCfg but not by the frame's chirps")
    logical = tuple(sum(1 << chans.index(c) for c in channel_bits(m)) for m in masks)
    n_tx = len(chans)
    order = None if st.ddm_order is None else \
        tuple(chans.index(t + 1) for t in st.ddm_order if t + 1 in chans)
    claim = None
    if st.bpm is not None:  # bpmCfg names its scheme: both Tx on the two coded chirps
        c0, c1, bln = st.bpm
        if n_tx != 2 or len(masks) != 2 or set(logical) != {3} or \
                (c0, c1) != (fr["start"], fr["start"] + 1):
            raise bln.fail(f"chirp0Idx={c0}, chirp1Idx={c1}: BPM needs a loop of exactly these "
                           "two chirps, both enabling the same two Tx")
        claim = {"mimo": MIMO_SCHEMES[TI_SCHEME_COMMANDS["bpmCfg"]].name, "tx_order": (1, 2)}
    for scheme in () if claim is not None else MIMO_SCHEMES.values():
        try:
            claim = scheme.from_ti(logical, n_tx, (1 << n_tx) - 1, order)
        except ValueError as exc:
            raise fln.fail(str(exc)) from None
        if claim is not None:
            break
    if claim is None:
        pattern = " ".join(f"0b{m:04b}" for m in masks)
        raise fln.fail(f"chirp Tx pattern [{pattern}] matches no MIMO scheme "
                       f"({', '.join(MIMO_SCHEMES)}): DDMA needs the same {n_tx} Tx every chirp "
                       f"and more than {n_tx} chirps per loop (classic DDMA exactly {n_tx}), "
                       "TDMA one Tx per chirp in a repeated sequence in which each Tx fires once")
    claim = dict(claim)
    tx_order = claim.pop("tx_order", None)
    st.set(fln, **claim, n_tx=n_tx, tx_channels=chans, n_chirps=len(masks) * fr["loops"])
    if "n_subbands" in claim:
        if st.ddm_order is None:
            st.notes.append("no ddmPhaseShiftAntOrder: the R79 demo's default order "
                            "(horizontal Tx first, elevation Tx last)")
    elif st.ddm_order is not None:
        st.ignored.append((st.seen["ddmPhaseShiftAntOrder"].no, "ddmPhaseShiftAntOrder"))
    if tx_order is not None:
        ln = st.seen["ddmPhaseShiftAntOrder"] if "n_subbands" in claim else fln
        st.set(ln, tx_order=tx_order)
    return claim
