"""Registry of TI evaluation boards: element positions and element patterns.

Positions are (y, z) in wavelengths in the radar frame (y to the left, z up, design.md 3), one per
Tx and Rx channel of the chip in TI's channel order (Tx1 = TI's Tx0). The virtual array, its
horizontal row and its raised rows follow from these positions for any Tx subset and order
(`RadarConfig.virtual_positions_m`, `pipeline.kernels.array_layout`).

Element patterns are cosine power patterns G0 cos(az)^n_az cos(el)^n_el (`radarsim.antenna`),
with n chosen so the one-way half-power angle matches the field of view the board's user guide
states: n = ln(0.5) / ln(cos(theta_3dB)).

Sources
-------
- AWR2944EVM: design.md 4.2 / [TI-DDMA] figure 20, and the ``antGeometryCfg 1 0 1 1 1 2 1 3 0 2 0 3
  0 4 0 5 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 0.5 0.8`` of TI's AWR294X profiles (mmWave MCU+ SDK
  ``profile_LVDS.cfg``; R79 / DDM demo): Tx1, Tx3, Tx4 at 0, 2, 4 lambda, Tx2 at 1 lambda and
  0.8 lambda up; Rx at lambda/2. Azimuth FOV +/-80 deg ([TI-DDMA] section 1).
- AWR2944PEVM: the AWR2944P visualizer profiles carry the same ``antGeometryCfg`` (same EVM
  antenna layout as the AWR2944EVM).
- AWR2544LOPEVM: the AWR2544 DDM demo orders ``ddmPhaseShiftAntOrder 0 1 2 3`` (no elevation
  Tx, which TI requires last); modelled as four azimuth Tx 2 lambda apart (a filled 16-element
  lambda/2 virtual row). NOT checked against the EVM drawing: give ``antGeometryCfg`` in the
  profile to override.
- AWR1843BOOST, IWR6843ISK: mmWave SDK 3.x xwr18xx / xwr68xx demo documentation, "antenna
  geometry": Tx1 and Tx3 2 lambda apart in azimuth, Tx2 between them (1 lambda) and lambda/2
  above; Rx at lambda/2 (8 azimuth + 4 elevation virtual elements). Azimuth FOV +/-60 deg,
  elevation +/-30 deg (BOOST / ISK user guides, approximate).
- AWR1642BOOST: Tx1 and Tx2 2 lambda apart, Rx at lambda/2 (8 virtual elements in one row;
  mmWave SDK xwr16xx demo documentation; [TI-VEXT]). FOV as the AWR1843BOOST.
- IWR6843AOPEVM (``% Platform:xWR68xx_AOP``): TI mmWave Industrial Toolbox 4.7.0, 3D people
  counting lab, ``chirp_configs/AOP_6m_default.cfg`` ``antGeometry0`` (azimuth) / ``antGeometry1``
  (elevation) virtual-element indices in lambda/2 units, Tx0..Tx2 x Rx0..Rx3 in that
  profile's chirp order (Tx masks 1, 2, 4; ``pcount3D_cli.c`` stores them as the Capon DoA's
  m_ind / n_ind): ``-1 -1 0 0 -3 -3 -2 -2 -1 -1 0 0`` / ``-1 0 -1 0 -3 -2 -3 -2 -3 -2 -3 -2``.
  The same lab's ``ISK_6m_default.cfg`` (``0 -1 -2 -3 -2 -3 -4 -5 -4 -5 -6 -7`` /
  ``-1 -1 -1 -1 0 0 0 0 -1 -1 -1 -1``) reproduces the ISK layout above with y = -m / 2 and
  z = n / 2; read the same way (z = n / 2 + 1, so that a 4-element row is the z = 0 row the
  azimuth FFT uses) the AOP has its four Rx in a lambda/2 square and Tx at (0, 1), (1, 0),
  (0, 0), Rx at (0.5, -0.5), (0.5, 0), (0, -0.5), (0, 0) lambda: a 4 x 4 lambda/2 virtual
  grid less one 2 x 2 corner, rows at z = 1, 0.5, 0 and -0.5 lambda
  (`pipeline.kernels.estimate_angles` combines the raised rows).
  The lab's ``antPhaseRot 1 -1 1 -1 ...`` (Rx2, Rx4 fed in antiphase; the SDK's AOP profiles
  say the same with ``compRangeBiasAndRxChanPhase 0.0 1 0 -1 0 ...``) is a channel phase, not
  geometry: a profile's line gives it (`pipeline.compensation.implied_board`). Element
  pattern: half power at +/-60 deg in both planes, ASSUMED (the toolbox's antenna page,
  ``antennas/ant_rad_patterns/iwr6843_aop/IWR6843aop.html``, calls it "wide field-of-view" and
  plots measured patterns without numbers).
- AWR1443BOOST: the mmWave SDK xwr14xx demo's documentation (its ``main.c`` doxygen, section
  "Antenna Configurations", as shipped in TI's mmWave Industrial Toolbox 4.7.0
  ``labs/level_sensing/14xx_high_accuracy/pjt/main.c``): "Transmit antennas Tx1 and Tx3 are
  horizontally spaced at d = 2 Lambda ... The third Tx antenna, Tx2, is positioned between the
  other two Tx antennas at half lambda elevation" -- the xWR18xx BOOST layout.
- AWR1243BOOST, AWR2243BOOST: ASSUMED to carry the same 3 Tx / 4 Rx layout (no TI document
  giving their antenna geometry was found with the code/pages search: the Industrial
  Toolbox's antenna database covers the IWR1443/1642/1843 BOOST and IWR6843 ISK/AOP/ODS
  only). Give ``antGeometryCfg`` (or a ``% radarsim:`` positions directive) to override.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from core.errors import BadInput
from core.registry import Registry

from .chips import get_chip

__all__ = ["Board", "BOARDS", "get_board", "register_board", "cos_exponent_for_half_power",
           "MAX_ELEMENT_OFFSET_WL"]

#: Largest element coordinate of a board, wavelengths (about 39 cm at 77 GHz): a single board's
#: array (TI's four-chip cascade spans about 43 wavelengths). Beyond it the element phases lose
#: float precision (1e300 wavelengths put NaN into the ADC frame) and the far-field signal
#: model stops holding at the ranges a corner radar sees.
MAX_ELEMENT_OFFSET_WL = 100.0


def cos_exponent_for_half_power(theta_deg: float) -> float:
    """n with cos(theta)^n = 1/2: the exponent of a cosine power pattern whose one-way gain is
    -3 dB at theta."""
    return math.log(0.5) / math.log(math.cos(math.radians(theta_deg)))


@dataclass(frozen=True, slots=True)
class Board:
    """One board: chip, element positions and element pattern.

    Attributes
    ----------
    tx_positions_wl, rx_positions_wl : tuple of (y, z)
        Element positions in wavelengths, Tx1.. and Rx1.. (TI's Tx0.., Rx0..).
    pattern_exponent_az, pattern_exponent_el : float
        Cosine power-pattern exponents (one way).
    fov_deg : float
        Azimuth field of view the user guide states, +/- deg (the association's visibility
        cone, `harness.cell.config.cell_association`).
    """

    name: str
    chip: str
    tx_positions_wl: tuple[tuple[float, float], ...]
    rx_positions_wl: tuple[tuple[float, float], ...]
    pattern_exponent_az: float
    pattern_exponent_el: float
    source: str
    fov_deg: float = 80.0
    #: TI Visualizer ``% Platform:`` name that means this board (e.g. ``xWR68xx_AOP``), or "".
    ti_platform: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise BadInput(f"board name={self.name!r} must be a non-empty string")
        chip = get_chip(self.chip)
        object.__setattr__(self, "tx_positions_wl", _positions(
            self.tx_positions_wl, chip.n_tx, f"board {self.name}: tx_positions_wl"))
        object.__setattr__(self, "rx_positions_wl", _positions(
            self.rx_positions_wl, chip.n_rx, f"board {self.name}: rx_positions_wl"))
        for fld in ("pattern_exponent_az", "pattern_exponent_el"):
            v = getattr(self, fld)
            if not (isinstance(v, (int, float)) and 0 <= v < math.inf):
                raise BadInput(f"board {self.name}: {fld}={v!r} must be a finite number >= 0")
        if not (isinstance(self.fov_deg, (int, float)) and 0 < self.fov_deg <= 90):
            raise BadInput(f"board {self.name}: fov_deg={self.fov_deg!r} must be in (0, 90]")
        if not isinstance(self.ti_platform, str):
            raise BadInput(f"board {self.name}: ti_platform={self.ti_platform!r} must be a "
                           "string (a TI Visualizer '% Platform:' name, or '')")

    # ------------------------------------------------------------------ configs
    def validate(self, cfg) -> None:
        """Check a `radarsim.RadarConfig` against this board: it carries the config's chip and
        explicit element positions hold one finite (y, z) pair per chip channel.

        Raises
        ------
        ValueError
            Naming the field, the value and the rule.
        """
        if self.chip != cfg.chip:
            raise BadInput(f"board={self.name!r} carries a {self.chip}, not chip="
                           f"{cfg.chip!r}")
        self.defaults(cfg)

    def defaults(self, cfg) -> dict[str, Any]:
        """The board-derived fields of a config, None resolved: element positions (checked)
        and pattern exponents."""
        chip = get_chip(self.chip)
        out = {}
        for side, n in (("tx", chip.n_tx), ("rx", chip.n_rx)):
            name = f"{side}_positions_wl"
            value = getattr(cfg, name)
            out[name] = _positions(getattr(self, name) if value is None else value, n, name)
        for name in ("pattern_exponent_az", "pattern_exponent_el"):
            value = getattr(cfg, name)
            out[name] = getattr(self, name) if value is None else value
        return out


def _positions(value, n: int, name: str) -> tuple[tuple[float, float], ...]:
    """`n` finite (y, z) pairs in wavelengths as a tuple of tuples.

    Raises
    ------
    ValueError
        Not a sequence of `n` finite pairs.
    """
    try:
        pos = tuple((float(y), float(z)) for y, z in value)
    except (TypeError, ValueError):
        raise BadInput(f"{name}={value!r} must be a sequence of (y, z) pairs in "
                       "wavelengths") from None
    if len(pos) != n or not all(math.isfinite(c) for p in pos for c in p):
        raise BadInput(f"{name} must hold {n} finite (y, z) pairs (one per chip channel), "
                       f"got {value!r}")
    far = [c for p in pos for c in p if abs(c) > MAX_ELEMENT_OFFSET_WL]
    if far:
        raise BadInput(f"{name}: element coordinate {far[0]:g} wavelengths is beyond "
                       f"+/-{MAX_ELEMENT_OFFSET_WL:g} (an antenna array on one board; the "
                       "far-field model needs it small against every range)")
    return pos


_RX_HALF_WAVE = ((0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.5, 0.0))
_AWR2944_TX = ((0.0, 0.0), (1.0, 0.8), (2.0, 0.0), (4.0, 0.0))
_XWR18_TX = ((0.0, 0.0), (1.0, 0.5), (2.0, 0.0))
# n_az = 1.2: -3 dB at +/-56 deg, -9 dB at +/-80 deg (usable +/-80 deg FOV); n_el = 4: -3 dB
# at +/-33 deg (the values the harness has always used for the AWR2944 EVM).
_EVM_AZ, _EVM_EL = 1.2, 4.0
_BOOST_AZ, _BOOST_EL = cos_exponent_for_half_power(60.0), cos_exponent_for_half_power(30.0)

#: Boards by name; `register_board` adds a lab's own.
BOARDS: Registry[Board] = Registry("board", kind=Board)
BOARDS.register_all((
    Board("AWR2944EVM", "AWR2944", _AWR2944_TX, _RX_HALF_WAVE, _EVM_AZ, _EVM_EL,
          "design.md 4.2, [TI-DDMA] fig. 20, TI antGeometryCfg"),
    Board("AWR2944PEVM", "AWR2944P", _AWR2944_TX, _RX_HALF_WAVE, _EVM_AZ,
          _EVM_EL, "AWR2944P visualizer antGeometryCfg (as AWR2944EVM)"),
    Board("AWR2544LOPEVM", "AWR2544",
          ((0.0, 0.0), (2.0, 0.0), (4.0, 0.0), (6.0, 0.0)), _RX_HALF_WAVE,
          _EVM_AZ, _EVM_EL,
          "assumed filled azimuth row (DDM demo order 0 1 2 3); unverified"),
    Board("AWR1843BOOST", "AWR1843", _XWR18_TX, _RX_HALF_WAVE, _BOOST_AZ,
          _BOOST_EL, "mmWave SDK xwr18xx demo antenna geometry", 60.0),
    Board("IWR6843ISK", "IWR6843", _XWR18_TX, _RX_HALF_WAVE, _BOOST_AZ, _BOOST_EL,
          "mmWave SDK xwr68xx demo antenna geometry (ISK as xWR18xx BOOST)",
          60.0),
    Board("IWR6843AOPEVM", "IWR6843", ((0.0, 1.0), (1.0, 0.0), (0.0, 0.0)),
          ((0.5, -0.5), (0.5, 0.0), (0.0, -0.5), (0.0, 0.0)),
          cos_exponent_for_half_power(60.0), cos_exponent_for_half_power(60.0),
          "TI mmWave Industrial Toolbox 4.7.0 3D people counting AOP_6m_default.cfg "
          "antGeometry0/antGeometry1", 60.0, ti_platform="xWR68xx_AOP"),
    Board("AWR1642BOOST", "AWR1642", ((0.0, 0.0), (2.0, 0.0)), _RX_HALF_WAVE,
          _BOOST_AZ, _BOOST_EL, "mmWave SDK xwr16xx demo; [TI-VEXT]", 60.0),
    *(Board(name, chip, _XWR18_TX, _RX_HALF_WAVE, _BOOST_AZ, _BOOST_EL,
            source, 60.0)
      for name, chip, source in (
          ("AWR1443BOOST", "AWR1443", "mmWave SDK xwr14xx demo antenna configurations"),
          ("AWR1243BOOST", "AWR1243", "as the xWR18xx BOOST layout; unverified"),
          ("AWR2243BOOST", "AWR2243", "as the xWR18xx BOOST layout; unverified"))),
))


def get_board(name: str) -> Board:
    """The board of that name; ValueError naming the known boards otherwise.

    Examples
    --------
    >>> from radarsim.boards import get_board
    >>> get_board("AWR2944EVM").tx_positions_wl[1]    # Tx2: 1 lambda over, 0.8 lambda up
    (1.0, 0.8)
    """
    return BOARDS.lookup(name)


def register_board(board: Board, *, replace: bool = False) -> Board:
    """Register a lab's own board (a `Board` record: chip, element positions, pattern) under
    ``board.name`` and return it; a config then names it in ``RadarConfig.board``.

    Raises
    ------
    ValueError
        A name already taken (without ``replace``), or not a `Board` (a `Board` itself checks
        its chip is registered and its positions fit the chip's channels).

    Examples
    --------
    >>> import radarsim
    >>> board = radarsim.Board("LAB_LOWRISE", "AWR2944",
    ...                        ((0, 0), (1, 0.5), (2, 0), (4, 0)),
    ...                        ((0, 0), (0.5, 0), (1, 0), (1.5, 0)), 1.2, 4.0, "a lab's board")
    >>> _ = radarsim.register_board(board)
    >>> cfg = radarsim.presets.r79_ddma(**{"array.board": "LAB_LOWRISE"})
    >>> round(float(cfg.tx_positions_m[1, 2] / cfg.wavelength_m), 2)
    0.5
    >>> _ = radarsim.BOARDS.unregister("LAB_LOWRISE")
    """
    return BOARDS.register(board, replace=replace)
