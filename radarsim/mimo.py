"""MIMO transmit schemes: how the transmitters share a frame, as pluggable scheme objects.

A scheme owns everything scheme-specific on the transmit side: its validation rules on a
`RadarConfig`, the transmit code (who transmits with which sign and phase at each chirp, before
the shifter's static and random errors), the slow-time layout (sub-bands or slots), the
unambiguous velocity it promises and the step by which a wrong velocity resolution is off.
`MIMO_SCHEMES` maps the names users type (``RadarConfig.mimo``) to scheme objects; a new
scheme is one module with a `MimoScheme` subclass plus one `register_scheme` call, and the
receive side registers its chain in ``pipeline.MIMO_CHAINS`` under the same name.

References
----------
.. [1] TI, "AWR2944 DDMA waveform for corner radar" (seed 000), section 3.2-3.3, tables 3-4.
.. [2] TI, "AWR1642 velocity disambiguation" (seed 001), TDMA Vmax = lambda / (4 Nt Tc).
.. [3] TI, xwr16xx mmWave SDK user guide, ``bpmCfg`` (slow-time binary phase modulation).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, NamedTuple

import numpy as np

if TYPE_CHECKING:  # config imports this module; the type is only needed for annotations
    from .config import RadarConfig

__all__ = ["MimoScheme", "TransmitCode", "SlowTimeLayout", "MIMO_SCHEMES", "register_scheme",
           "scheme_of", "DdmaScheme", "TdmaScheme"]


class TransmitCode(NamedTuple):
    """Ideal transmit code of a frame, before static and random shifter errors.

    Attributes
    ----------
    gain : (n_tx, n_chirps) float
        Amplitude and sign of each Tx at each chirp: 1 on, 0 silent, -1 sign-inverted (BPM).
    phase_rad : (n_tx, n_chirps) float
        Phase applied by each Tx's shifter at each chirp, rad (DDMA: the negated, possibly
        quantised programmed phase, seed 000 table 3-4).
    """

    gain: np.ndarray
    phase_rad: np.ndarray

    @property
    def weights(self) -> np.ndarray:
        """(n_tx, n_chirps) complex transmit weights gain x exp(j phase)."""
        return self.gain * np.exp(1j * self.phase_rad)


class SlowTimeLayout(NamedTuple):
    """How the transmitters share slow time.

    Attributes
    ----------
    n_groups : int
        Sub-bands (DDMA: Doppler sub-bands of the full spectrum) or slots per code period
        (TDMA, BPM: chirps of one cycle).
    group_of_tx : tuple of int
        Sub-band or slot position of Tx1..Tx{n_tx} (0-based), for DDMA the Doppler shift in
        sub-bands, for TDMA the slot the Tx fires in, for BPM the row of the code matrix.
    slow_time_period_s : float
        Sampling period of one transmitter's slow-time sequence after separation, s.
    n_doppler_bins : int
        Doppler bins per transmitter after separation.
    """

    n_groups: int
    group_of_tx: tuple[int, ...]
    slow_time_period_s: float
    n_doppler_bins: int


@dataclass(frozen=True)
class MimoScheme:
    """Base of the transmit schemes; subclasses override the methods that differ.

    Attributes
    ----------
    name : str
        Registry key (`RadarConfig.mimo`, the results' ``scheme`` column).
    description : str
        One line for help texts and reports.
    """

    name: str
    description: str
    #: True if the scheme programs per-chirp Tx phases (chips without shifters cannot run it).
    needs_phase_shifter: ClassVar[bool] = False

    # ------------------------------------------------------------------ configuration
    def default_n_subbands(self, n_tx: int) -> int:
        """`RadarConfig.n_subbands` when not given (empty-band rule: Nt + 2 for Nt = 4, else
        Nt + 1; schemes without sub-bands keep it but ignore it)."""
        return n_tx + 2 if n_tx == 4 else n_tx + 1

    def validate(self, cfg: "RadarConfig") -> None:
        """Scheme rules on a config (called by `RadarConfig.__post_init__`).

        Raises
        ------
        ValueError
            Naming the field, its value and the limit.
        """

    def chirps_per_period(self, cfg: "RadarConfig") -> int:
        """Chirps of one code period (the TI loop): n_chirps must be a multiple."""
        return cfg.n_tx

    def _check_divisible(self, cfg: "RadarConfig", what: str) -> None:
        per = self.chirps_per_period(cfg)
        if cfg.n_chirps % per:
            raise ValueError(f"n_chirps={cfg.n_chirps} must be divisible by {what}={per} for "
                             f"{self.name.upper()}")

    # ------------------------------------------------------------------ transmit side
    def transmit_code(self, cfg: "RadarConfig") -> TransmitCode:
        """(n_tx, n_chirps) ideal transmit gains and phases of one frame."""
        raise NotImplementedError

    def layout(self, cfg: "RadarConfig") -> SlowTimeLayout:
        """Slot / sub-band layout of the scheme."""
        raise NotImplementedError

    # ------------------------------------------------------------------ promises
    def slow_time_period_s(self, cfg: "RadarConfig") -> float:
        """Sampling period of one Tx's slow-time sequence, s (TDMA, BPM: n_tx Tc)."""
        return cfg.chirp_period_s * cfg.n_tx

    def max_unambiguous_velocity_mps(self, cfg: "RadarConfig") -> float:
        """lambda / (4 T) with T the slow-time period of one transmitter, m/s."""
        return cfg.wavelength_m / (4 * self.slow_time_period_s(cfg))

    def n_doppler_bins(self, cfg: "RadarConfig") -> int:
        """Doppler bins per transmitter after separation."""
        return cfg.n_chirps // cfg.n_tx

    def velocity_failure_step_mps(self, cfg: "RadarConfig") -> float:
        """Step by which a wrong velocity resolution is off, m/s: one sub-band (DDMA) or the
        unambiguous span 2 Vmax of one transmitter's sequence (TDMA, BPM)."""
        return 2 * self.max_unambiguous_velocity_mps(cfg)


# ------------------------------------------------------------------------------ DDMA
@dataclass(frozen=True)
class DdmaScheme(MimoScheme):
    """Doppler-division MIMO: all Tx every chirp, Tx in sub-band p steps its phase by
    2 pi p / N per chirp (seed 000 section 3.3). With empty sub-bands (N > Nt) the
    demodulation resolves Tx and velocity over +/- lambda / (4 Tc) (table 11).

    Attributes
    ----------
    empty_band : bool
        True: N > Nt (at least one empty sub-band); False: classic DDMA, N = Nt.
    """

    empty_band: bool = True
    needs_phase_shifter: ClassVar[bool] = True

    def default_n_subbands(self, n_tx: int) -> int:
        return super().default_n_subbands(n_tx) if self.empty_band else n_tx

    def chirps_per_period(self, cfg: "RadarConfig") -> int:
        return cfg.n_subbands

    def validate(self, cfg: "RadarConfig") -> None:
        n_sb = cfg.n_subbands
        if self.empty_band:
            if not isinstance(n_sb, (int, np.integer)) or n_sb <= cfg.n_tx:
                raise ValueError(f"n_subbands={n_sb!r} must be an integer > n_tx={cfg.n_tx} "
                                 "(empty-band DDMA needs at least one empty band)")
        elif n_sb != cfg.n_tx:
            raise ValueError(f"n_subbands={n_sb!r} must equal n_tx={cfg.n_tx} for "
                             f"{self.name} (classic DDMA: one sub-band per Tx, no empty band)")
        if cfg.n_chirps % n_sb:
            raise ValueError(f"n_chirps={cfg.n_chirps} must be divisible by the number of "
                             f"DDMA sub-bands n_subbands={n_sb}")

    def transmit_code(self, cfg: "RadarConfig") -> TransmitCode:
        c = np.arange(cfg.n_chirps)
        phase = cfg.applied_phase_rad()[:, c % cfg.n_subbands]
        return TransmitCode(np.ones((cfg.n_tx, cfg.n_chirps)), phase)

    def layout(self, cfg: "RadarConfig") -> SlowTimeLayout:
        return SlowTimeLayout(cfg.n_subbands, tuple(cfg.subband_of_tx[t]
                                                    for t in range(1, cfg.n_tx + 1)),
                              self.slow_time_period_s(cfg), self.n_doppler_bins(cfg))

    def slow_time_period_s(self, cfg: "RadarConfig") -> float:
        return cfg.chirp_period_s * 1  # every Tx fires every chirp

    def n_doppler_bins(self, cfg: "RadarConfig") -> int:
        return cfg.n_chirps // cfg.n_subbands

    def velocity_failure_step_mps(self, cfg: "RadarConfig") -> float:
        return cfg.subband_width_mps


# ------------------------------------------------------------------------------ TDMA
@dataclass(frozen=True)
class TdmaScheme(MimoScheme):
    """Time-division MIMO: one Tx per chirp, in turn (`tx_order` gives the slots), so each
    Tx samples slow time at n_tx Tc: Vmax = lambda / (4 Nt Tc) (seed 001)."""

    def validate(self, cfg: "RadarConfig") -> None:
        if cfg.n_chirps % cfg.n_tx:
            raise ValueError(f"n_chirps={cfg.n_chirps} must be divisible by n_tx={cfg.n_tx} "
                             "for TDMA")

    def transmit_code(self, cfg: "RadarConfig") -> TransmitCode:
        c = np.arange(cfg.n_chirps)
        slot_tx = np.array(cfg.tx_order)[c % cfg.n_tx]  # 1-based Tx firing at chirp c
        on = (slot_tx[None, :] == np.arange(1, cfg.n_tx + 1)[:, None]).astype(float)
        return TransmitCode(on, np.zeros((cfg.n_tx, cfg.n_chirps)))

    def layout(self, cfg: "RadarConfig") -> SlowTimeLayout:
        return SlowTimeLayout(cfg.n_tx, tuple(cfg.subband_of_tx[t]
                                              for t in range(1, cfg.n_tx + 1)),
                              self.slow_time_period_s(cfg), self.n_doppler_bins(cfg))


#: Registry of MIMO schemes by the name users type (`RadarConfig.mimo`).
MIMO_SCHEMES: dict[str, MimoScheme] = {}


def register_scheme(scheme: MimoScheme, *, replace: bool = False) -> MimoScheme:
    """Add a scheme to `MIMO_SCHEMES` under `scheme.name` and return it.

    Raises
    ------
    ValueError
        If the name is taken (and `replace` is False) or not a non-empty identifier.
    """
    if not isinstance(scheme, MimoScheme):
        raise ValueError(f"scheme must be a MimoScheme, got {type(scheme).__name__}")
    if not scheme.name.isidentifier():
        raise ValueError(f"scheme name={scheme.name!r} must be a non-empty identifier")
    if scheme.name in MIMO_SCHEMES and not replace:
        raise ValueError(f"scheme name={scheme.name!r} is already registered")
    MIMO_SCHEMES[scheme.name] = scheme
    return scheme


def scheme_of(name: str) -> MimoScheme:
    """The registered scheme called `name`.

    Raises
    ------
    ValueError
        Naming the unknown value and the registered names.
    """
    try:
        return MIMO_SCHEMES[name]
    except (KeyError, TypeError):
        raise ValueError(f"mimo={name!r} is not one of {sorted(MIMO_SCHEMES)}") from None


register_scheme(DdmaScheme("ddma", "Doppler-division: all Tx every chirp, per-Tx phase step, "
                                   "empty sub-bands"))
register_scheme(TdmaScheme("tdma", "time-division: one Tx per chirp, in turn"))
