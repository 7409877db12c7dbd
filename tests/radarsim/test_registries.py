"""The one registry helper behind every registry, and a lab's own chip and board.

A lab registers its hardware exactly as it registers a MIMO scheme (`radarsim.register_chip`,
`radarsim.register_board`); the config validates against it and the whole chain runs on it.
"""
from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

import pipeline
import radarsim
from core.registry import Registry
from pipeline.cfar import CFAR_MODES
from pipeline.mimo.base import MIMO_CHAINS
from radarsim.boards import BOARDS, Board
from radarsim.chips import ADC_MODES, CHIPS
from scenarios import SCENARIOS

# ----------------------------------------------------------------------------- the helper


class _Part:
    def __init__(self, name: str) -> None:
        self.name = name


def test_register_lookup_replace_unregister_freeze():
    reg = Registry("part", field="part", kind=_Part)
    a = reg.register(_Part("a"))
    assert reg.lookup("a") is a and reg["a"] is a and list(reg) == ["a"] and len(reg) == 1
    with pytest.raises(ValueError, match=r"part name='a' is already registered"):
        reg.register(_Part("a"))
    b = reg.register(_Part("a"), replace=True)
    assert reg.lookup("a") is b
    reg["c"] = _Part("c")                      # the dict idiom registers (replacing)
    assert sorted(reg) == ["a", "c"]
    del reg["c"]
    assert "c" not in reg
    reg.freeze()
    with pytest.raises(ValueError, match=r"the part registry is frozen"):
        reg.register(_Part("d"))
    with pytest.raises(ValueError, match=r"the part registry is frozen"):
        reg.unregister("a")


_BAD_REGISTRATIONS = [
    (dict(obj="not a part"), r"part must be a _Part, got str"),
    (dict(obj=_Part("")), r"part name='' must be a non-empty string"),
    (dict(obj=_Part("a b"), identifier=True), r"part name='a b' must be a non-empty identifier"),
]


@pytest.mark.parametrize("case,match", _BAD_REGISTRATIONS, ids=[m for _, m in _BAD_REGISTRATIONS])
def test_bad_registrations(case, match):
    reg = Registry("part", kind=_Part, identifier=case.get("identifier", False))
    with pytest.raises(ValueError, match=match):
        reg.register(case["obj"])


def test_lookup_error_lists_every_known_name():
    reg = Registry("part", field="kind", kind=_Part).register_all([_Part("b"), _Part("a")])
    with pytest.raises(ValueError, match=r"^kind='z' is not one of \['a', 'b'\]$"):
        reg.lookup("z")
    with pytest.raises(ValueError, match=r"kind=\['a'\] is not one of"):
        reg.lookup(["a"])                      # unhashable: simply not found


@pytest.mark.parametrize("registry,field", [
    (radarsim.MIMO_SCHEMES, "mimo"), (CHIPS, "chip"), (BOARDS, "board"),
    (ADC_MODES, "adc_mode"), (CFAR_MODES, "mode"), (MIMO_CHAINS, "mimo")],
    ids=["schemes", "chips", "boards", "adc_modes", "cfar_modes", "chains"])
def test_every_registry_is_the_one_helper(registry, field):
    assert isinstance(registry, Registry) and registry.field == field
    with pytest.raises(ValueError, match=rf"{field}='nope' (is not one of|has no receive)"):
        registry.lookup("nope")


def test_closed_vocabularies_are_frozen():
    assert ADC_MODES.frozen
    with pytest.raises(ValueError, match="frozen"):
        ADC_MODES.register(ADC_MODES["real"], name="real4x")


def test_the_case_catalogue_is_a_registry():
    assert isinstance(SCENARIOS, Registry)
    with pytest.raises(ValueError, match=r"unknown scenario 'nope'; known: .*r79_motorcycle"):
        SCENARIOS.lookup("nope")


# ----------------------------------------------------------------------------- a lab's hardware

#: A lab's board for the AWR2944: the EVM's Tx1/Tx3/Tx4 row, but Tx2 only 0.5 lambda above
#: (elevation unambiguous over +/-90 deg instead of +/-38.7) and a narrower FOV.
LAB_BOARD = Board("LAB_AWR2944_LOWRISE", "AWR2944",
                  ((0.0, 0.0), (1.0, 0.5), (2.0, 0.0), (4.0, 0.0)),
                  ((0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.5, 0.0)), 1.2, 4.0,
                  "a lab's own board (test)", 70.0)


@pytest.fixture
def lab_board():
    board = radarsim.register_board(LAB_BOARD)
    yield board
    BOARDS.unregister(board.name)


@pytest.fixture
def lab_chip():
    """An AWR2944 whose synthesizer a lab limits to 76-77 GHz, with its own board."""
    chip = dataclasses.replace(CHIPS["AWR2944"], name="LAB2944_76G", band_max_hz=77e9,
                               default_board="LAB2944_76G_EVM")
    radarsim.register_chip(chip)
    board = radarsim.register_board(dataclasses.replace(BOARDS["AWR2944EVM"],
                                                        name="LAB2944_76G_EVM",
                                                        chip="LAB2944_76G"))
    yield chip
    BOARDS.unregister(board.name)
    CHIPS.unregister(chip.name)


def test_a_labs_board_runs_a_frame(lab_board):
    """Register from outside the tree, then simulate and process a frame on it: the target is
    found where it is, and the elevation follows the board's own 0.5-lambda baseline."""
    cfg = radarsim.presets.r79_ddma(board=lab_board.name)
    assert cfg.board == lab_board.name
    np.testing.assert_allclose(cfg.tx_positions_m[1, 1:],
                               0.5 * cfg.wavelength_m * np.array([2.0, 1.0]))
    rng = np.random.default_rng(3)
    sc = radarsim.Scatterers.from_spherical([40.0], [20.0], [10.0], [-5.0], [10.0])
    pc = pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, sc, rng))
    best = pc.loc[pc["snr_db"].idxmax()]
    assert best["range_m"] == pytest.approx(40.0, abs=cfg.range_resolution_m)
    assert best["radial_velocity_mps"] == pytest.approx(-5.0, abs=cfg.velocity_resolution_mps)
    # Azimuth within half the 12-element resolution (asin(2/12) = 9.6 deg).
    assert best["azimuth_deg"] == pytest.approx(20.0, abs=4.8)
    # Elevation from wz = 2 pi 0.5 sin(el): a pipeline that assumed the EVM's 0.8 lambda would
    # report asin(0.5 / 0.8 sin 10 deg) = 6.2 deg.
    assert best["elevation_deg"] == pytest.approx(10.0, abs=2.0)


def test_a_labs_board_must_fit_its_chip():
    with pytest.raises(ValueError, match=r"tx_positions_wl must hold 4 finite"):
        Board("LAB_BAD", "AWR2944", ((0.0, 0.0),), LAB_BOARD.rx_positions_wl, 1.0, 1.0, "x")
    with pytest.raises(ValueError, match=r"chip='AWR9999' is not one of"):
        Board("LAB_BAD", "AWR9999", LAB_BOARD.tx_positions_wl, LAB_BOARD.rx_positions_wl,
              1.0, 1.0, "x")
    with pytest.raises(ValueError, match=r"board name='AWR2944EVM' is already registered"):
        radarsim.register_board(dataclasses.replace(LAB_BOARD, name="AWR2944EVM"))


def test_a_boards_ti_platform_must_be_a_string():
    with pytest.raises(ValueError, match=r"board LAB_BAD: ti_platform=68 must be a string"):
        dataclasses.replace(LAB_BOARD, name="LAB_BAD", ti_platform=68)


def test_a_board_of_another_chip_is_refused(lab_board):
    with pytest.raises(ValueError, match=r"board='LAB_AWR2944_LOWRISE' carries a AWR2944, "
                                         r"not chip='AWR1843'"):
        radarsim.RadarConfig.from_fields(chip="AWR1843", board=lab_board.name, mimo="tdma", n_tx=3)


def test_a_labs_chip_limits_its_configs(lab_chip):
    cfg = radarsim.presets.r79_ddma(chip=lab_chip.name, start_freq_hz=76.2e9)
    assert cfg.board == "LAB2944_76G_EVM" and cfg.chip_spec is lab_chip
    top = 77e9 + 8.883e12 * 18.81e-6
    with pytest.raises(ValueError, match=re.escape(f"ramp end frequency {top:g} Hz exceeds "
                                                   "the LAB2944_76G band limit 7.7e+10 Hz")):
        radarsim.presets.r79_ddma(chip=lab_chip.name)


def test_a_bad_chip_record_is_refused():
    base = CHIPS["AWR2944"]
    with pytest.raises(ValueError, match=r"band_min_hz=8.1e\+10 and band_max_hz=7.6e\+10"):
        dataclasses.replace(base, name="LAB", band_min_hz=81e9, band_max_hz=76e9)
    with pytest.raises(ValueError, match=r"chip LAB: n_tx=0 must be an integer >= 1"):
        dataclasses.replace(base, name="LAB", n_tx=0)
    with pytest.raises(ValueError, match=r"chip LAB: adc modes \['real8x'\] must be"):
        dataclasses.replace(base, name="LAB", adc={"real8x": base.adc["real"]})
    assert math.isfinite(base.band_max_hz)


@pytest.mark.parametrize("limits", [float("nan"), "fast", -1.0, 0.0, float("inf"), True],
                         ids=["nan", "string", "negative", "zero", "inf", "true"])
def test_a_chip_records_adc_limits_are_checked(limits):
    """NaN removed the rate limit, a string gave a TypeError at the first config, -1 made every
    config fail while blaming the config."""
    from radarsim.chips import AdcLimits
    with pytest.raises(ValueError, match=r"chip LAB: adc\['real'\]=AdcLimits\(max_rate_sps=.*\) "
                                         r"must be AdcLimits with max_rate_sps a finite number"):
        dataclasses.replace(CHIPS["AWR2944"], name="LAB", adc={"real": AdcLimits(limits)})


def test_a_chip_records_adc_mode_needs_adc_limits():
    with pytest.raises(ValueError, match=r"adc\['real'\]=37500000\.0 must be AdcLimits"):
        dataclasses.replace(CHIPS["AWR2944"], name="LAB", adc={"real": 37.5e6})


@pytest.mark.parametrize("field, value, match", [
    ("max_loops", 10**9, r"max_loops=1000000000 exceeds 255 \(rlFrameCfg_t\.numLoops"),
    ("max_chirp_defs", 4096, r"max_chirp_defs=4096 exceeds 512"),
    ("max_profiles", 5, r"max_profiles=5 exceeds 4"),
    ("max_adc_samples", 10**6, r"max_adc_samples=1000000 exceeds 65535"),
])
def test_a_chip_records_counts_are_bounded(field, value, match):
    """max_loops=1e9 let a config of 1e9 chirps through to a MemoryError."""
    with pytest.raises(ValueError, match=r"chip LAB: " + match):
        dataclasses.replace(CHIPS["AWR2944"], name="LAB", **{field: value})


def test_a_board_element_far_away_is_refused():
    """An element at 1e300 wavelengths put NaN into the int16 ADC frame (a RuntimeWarning)."""
    far = ((0.0, 0.0), (1e300, 0.8), (2.0, 0.0), (4.0, 0.0))
    with pytest.raises(ValueError, match=r"board LAB_FAR: tx_positions_wl: element coordinate "
                                         r"1e\+300 wavelengths is beyond \+/-100"):
        dataclasses.replace(LAB_BOARD, name="LAB_FAR", tx_positions_wl=far)
    with pytest.raises(ValueError, match=r"tx_positions_wl: element coordinate 1e\+300"):
        radarsim.presets.r79_ddma(**{"array.tx_positions_wl": far})


def test_replace_must_be_a_bool():
    """replace="yes" replaced a registered chip without a word."""
    with pytest.raises(ValueError, match=r"replace='yes' must be true or false"):
        radarsim.register_chip(CHIPS["AWR2944"], replace="yes")
