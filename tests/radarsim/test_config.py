"""RadarConfig: derived values of the R79 preset, table-4 DDMA codes, every validation rule.

References are design.md section 8 (derived values) and [TI-DDMA] tables 2-4 (waveform, codes);
validation rules are design.md 4.4 plus the domain checks of `RadarConfig.__post_init__`.
"""
from __future__ import annotations

import copy
import dataclasses
import math
import pickle

import numpy as np
import pytest

import radarsim
from radarsim.config import C_MPS, K_BOLTZMANN, RadarConfig


# ----------------------------------------------------------------------------- derived values
def test_derived_values_match_design_section_8(make_config):
    """design.md 8: 1.318 m, 253 m, 0.1065 m/s, +/-40.9 m/s, 13.63 m/s sub-band, 18.29 ms."""
    cfg = make_config("ddma")
    assert cfg.wavelength_m == pytest.approx(C_MPS / 77e9)
    assert cfg.sampled_bandwidth_hz == pytest.approx(113.7e6, rel=1e-3)
    assert cfg.range_resolution_m == pytest.approx(1.318, abs=5e-4)
    assert cfg.n_range_bins == 192
    assert cfg.max_range_m == pytest.approx(253.0, abs=0.5)
    assert cfg.velocity_resolution_mps == pytest.approx(0.1065, abs=5e-5)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(40.9, abs=0.05)
    assert cfg.subband_width_mps == pytest.approx(13.63, abs=5e-3)
    assert cfg.frame_time_s == pytest.approx(18.29e-3, abs=5e-6)
    assert cfg.n_subbands == 6
    assert cfg.n_doppler_bins == 128
    assert cfg.n_virtual == 16
    # Sub-band width times the number of sub-bands is the full unambiguous span 2 Vmax.
    assert cfg.subband_width_mps * cfg.n_subbands == pytest.approx(
        2 * cfg.max_unambiguous_velocity_mps)


def test_tdma_derived_values_match_design_section_8(make_config):
    """design.md 8 / [TI-VEXT]: TDMA Vmax = lambda / (16 Tc) = 10.22 m/s, same frame time and
    velocity resolution as DDMA, 192 Doppler bins per Tx."""
    ddma, tdma = make_config("ddma"), make_config("tdma")
    assert tdma.max_unambiguous_velocity_mps == pytest.approx(10.22, abs=5e-3)
    assert tdma.max_unambiguous_velocity_mps == pytest.approx(
        ddma.max_unambiguous_velocity_mps / 4)
    assert tdma.n_chirps == ddma.n_chirps == 768
    assert tdma.frame_time_s == pytest.approx(ddma.frame_time_s)
    assert tdma.velocity_resolution_mps == pytest.approx(ddma.velocity_resolution_mps)
    assert tdma.n_doppler_bins == 192


def test_noise_power_is_k_t_nf_b(make_config):
    """k T NF B with B = adc_rate / 2 (real samples, Nyquist band)."""
    cfg = make_config()
    expected = K_BOLTZMANN * 290.0 * 10 ** (12.0 / 10) * 15e6
    assert cfg.noise_power_w == pytest.approx(expected, rel=1e-12)
    # A full-scale sine (adc_full_scale_dbm) has peak 32767 LSB.
    p_fs = 1e-3 * 10 ** (cfg.adc_full_scale_dbm / 10)
    assert math.sqrt(2 * p_fs) * cfg.adc_code_per_sqrt_w == pytest.approx(32767)
    assert cfg.noise_rms_lsb == pytest.approx(math.sqrt(expected) * cfg.adc_code_per_sqrt_w)


# ----------------------------------------------------------------------------- DDMA codes
def test_phase_codes_floor_reproduce_seed_table_4(make_config):
    """[TI-DDMA] table 4 (floor rule): rows Tx1..Tx4 over the 6-chirp code period."""
    cfg = make_config()
    assert cfg.phase_quantization == "floor"
    codes = cfg.phase_codes()
    assert codes.shape == (4, 6)
    np.testing.assert_array_equal(codes[0], [0, 0, 0, 0, 0, 0])          # Tx1
    np.testing.assert_array_equal(codes[2], [0, 53, 42, 32, 21, 10])     # Tx3
    np.testing.assert_array_equal(codes[3], [0, 42, 21, 0, 42, 21])      # Tx4
    np.testing.assert_array_equal(codes[1], [0, 32, 0, 32, 0, 32])       # Tx2
    # Table 4's quantised phases: Tx3 0, 298.125, 236.25, 180, 118.125, 56.25 deg.
    np.testing.assert_allclose(codes[2] * cfg.phase_lsb_deg,
                               [0, 298.125, 236.25, 180, 118.125, 56.25])
    assert cfg.phase_lsb_deg == 5.625


def test_phase_codes_round_rule_gives_sdk_codes(make_config):
    """TI SDK rounds to the nearest code (design.md 4.3): 300/5.625 = 53.3 -> 53,
    240/5.625 = 42.7 -> 43, 60/5.625 = 10.7 -> 11; error at most half an LSB (2.81 deg)."""
    cfg = make_config(phase_quantization="round")
    codes = cfg.phase_codes()
    np.testing.assert_array_equal(codes[2], [0, 53, 43, 32, 21, 11])
    np.testing.assert_array_equal(codes[3], [0, 43, 21, 0, 43, 21])
    np.testing.assert_array_equal(codes[1], [0, 32, 0, 32, 0, 32])
    err = np.angle(np.exp(1j * np.radians(cfg.programmed_phase_deg()
                                          - codes * cfg.phase_lsb_deg)), deg=True)
    assert np.max(np.abs(err)) <= 5.625 / 2 + 1e-9


def test_programmed_phase_is_negated_step_in_tx1_tx3_tx4_tx2_order(make_config):
    """[TI-DDMA] table 3: Tx1 0; Tx3 300, 240, ...; Tx4 240, 120, ...; Tx2 180, 0, ...;
    the applied phase (shifter delays) advances by +60, +120, +180 deg per chirp."""
    cfg = make_config(phase_quantization="none")
    prog = cfg.programmed_phase_deg()
    np.testing.assert_allclose(prog[2], [0, 300, 240, 180, 120, 60])
    np.testing.assert_allclose(prog[3], [0, 240, 120, 0, 240, 120])
    np.testing.assert_allclose(prog[1], [0, 180, 0, 180, 0, 180])
    assert cfg.subband_of_tx == {1: 0, 3: 1, 4: 2, 2: 3}
    step = np.angle(np.exp(1j * np.diff(cfg.applied_phase_rad(), axis=1)), deg=True)
    np.testing.assert_allclose(step[[0, 2, 3]], [[0] * 5, [60] * 5, [120] * 5], atol=1e-9)
    np.testing.assert_allclose(np.abs(step[1]), 180, atol=1e-9)


def test_virtual_positions_follow_evm_geometry(make_config):
    """design.md 4.2: 12 horizontal elements at lambda/2 (0..11), Tx2's 4 at 2..5, 0.8 lambda up."""
    cfg = make_config()
    v = cfg.virtual_positions_m / cfg.wavelength_m
    np.testing.assert_allclose(v[:12, 1], 0.5 * np.arange(12), atol=1e-12)
    np.testing.assert_allclose(v[:12, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(v[12:, 1], 0.5 * np.arange(2, 6), atol=1e-12)
    np.testing.assert_allclose(v[12:, 2], 0.8, atol=1e-12)
    np.testing.assert_allclose(v[:, 0], 0.0)


# ----------------------------------------------------------------------------- validation
# One rule per case: (overrides, regex naming the field). design.md 4.4 first, then domain checks.
R79 = dict(mimo="ddma")
VALIDATION_CASES = {
    # design.md 4.4
    "adc_rate_above_37.5Msps": (dict(adc_rate_sps=40e6), r"adc_rate_sps=4e\+07.*3\.75e\+07"),
    "if_bandwidth_above_15MHz": (dict(adc_rate_sps=36e6), r"adc_rate_sps=3\.6e\+07.*IF.*1\.5e\+07"),
    "ramp_above_81GHz": (dict(start_freq_hz=80.9e9),
                         r"start_freq_hz=8\.09e\+10 \+ slope_hz_per_s=8\.883e\+12.*8\.1e\+10"),
    "start_below_76GHz": (dict(start_freq_hz=75e9), r"start_freq_hz=7\.5e\+10.*7\.6e\+10"),
    "adc_window_outside_ramp": (dict(n_samples=512), r"n_samples=512.*ramp_end_time_s"),
    "chirp_period_not_idle_plus_ramp": (dict(chirp_period_s=25e-6),
                                        r"chirp_period_s=2\.5e-05.*idle_time_s"),
    "n_tx_zero": (dict(n_tx=0), r"n_tx=0.*1\.\.4"),
    "n_tx_five": (dict(n_tx=5), r"n_tx=5.*1\.\.4"),
    "n_tx_not_int": (dict(n_tx=2.0), r"n_tx=2\.0.*integer"),
    "n_rx_zero": (dict(n_rx=0), r"n_rx=0.*1\.\.4"),
    "n_rx_five": (dict(n_rx=5), r"n_rx=5.*1\.\.4"),
    "ddma_chirps_not_multiple_of_subbands": (dict(n_chirps=772),
                                             r"n_chirps=772.*n_subbands=6"),
    "tdma_chirps_not_multiple_of_n_tx": (dict(mimo="tdma", n_chirps=770),
                                         r"n_chirps=770.*n_tx=4"),
    "phase_shifter_not_6_bits": (dict(phase_shifter_bits=5), r"phase_shifter_bits=5.*6 bits"),
    # Domain checks of __post_init__
    "mimo_unknown": (dict(mimo="cdma"), r"mimo='cdma'"),
    "n_samples_below_2": (dict(n_samples=1), r"n_samples=1.*>= 2"),
    "n_samples_odd": (dict(n_samples=383), r"n_samples=383.*even"),
    "n_chirps_below_2": (dict(n_chirps=1), r"n_chirps=1.*>= 2"),
    "n_chirps_not_int": (dict(n_chirps=768.0), r"n_chirps=768\.0.*integer"),
    "adc_start_negative": (dict(adc_start_time_s=-1e-6), r"adc_start_time_s=-1e-06"),
    "phase_quantization_unknown": (dict(phase_quantization="ceil"),
                                   r"phase_quantization='ceil'"),
    "antenna_pattern_unknown": (dict(antenna_pattern="horn"), r"antenna_pattern='horn'"),
    "tx_order_not_permutation": (dict(tx_order=(1, 2, 3, 3)), r"tx_order=\(1, 2, 3, 3\)"),
    "tx_order_wrong_tx": (dict(tx_order=(1, 2, 5, 3)), r"tx_order=.*Tx 1\.\.4"),
    "n_subbands_not_above_n_tx": (dict(n_subbands=4), r"n_subbands=4.*n_tx=4"),
    "tx_phase_error_wrong_length": (dict(tx_phase_error_deg=(1.0, 2.0)),
                                    r"tx_phase_error_deg.*4 finite"),
    "tx_phase_error_nan": (dict(tx_phase_error_deg=(0.0, 0.0, float("nan"), 0.0)),
                           r"tx_phase_error_deg.*finite"),
    "tx_gain_error_wrong_length": (dict(tx_gain_error_db=(0.0,) * 5),
                                   r"tx_gain_error_db.*4 finite"),
    "tx_gain_error_inf": (dict(tx_gain_error_db=(0.0, float("inf"), 0.0, 0.0)),
                          r"tx_gain_error_db.*finite"),
}
for _name in ("start_freq_hz", "slope_hz_per_s", "idle_time_s", "ramp_end_time_s",
              "chirp_period_s", "adc_rate_sps", "temperature_k"):
    VALIDATION_CASES[f"{_name}_not_positive"] = (dict([(_name, 0.0)]),
                                                 rf"{_name}=0\.0 must be a finite positive")
    VALIDATION_CASES[f"{_name}_nan"] = (dict([(_name, float("nan"))]),
                                        rf"{_name}=nan must be a finite positive")
for _name in ("tx_power_dbm", "tx_antenna_gain_dbi", "rx_antenna_gain_dbi", "noise_figure_db",
              "system_loss_db", "adc_full_scale_dbm", "phase_noise_deg_rms",
              "pattern_exponent_az", "pattern_exponent_el"):
    VALIDATION_CASES[f"{_name}_inf"] = (dict([(_name, float("inf"))]),
                                        rf"{_name}=inf must be finite")
for _name in ("noise_figure_db", "system_loss_db", "phase_noise_deg_rms",
              "pattern_exponent_az", "pattern_exponent_el"):
    VALIDATION_CASES[f"{_name}_negative"] = (dict([(_name, -1.0)]), rf"{_name}=-1\.0 must be >= 0")


@pytest.mark.parametrize("overrides, match", list(VALIDATION_CASES.values()),
                         ids=list(VALIDATION_CASES))
def test_validation_rule_raises_naming_field(overrides, match):
    with pytest.raises(ValueError, match=match):
        RadarConfig.from_fields(**overrides)


def test_r79_preset_sits_inside_every_limit(make_config):
    """design.md 4.4: 5 + 12.8 us <= 18.81 us; 5 + 18.81 = 23.81 us; 77 + 0.167 GHz <= 81 GHz."""
    cfg = make_config()
    assert cfg.adc_start_time_s + cfg.n_samples / cfg.adc_rate_sps == pytest.approx(17.8e-6)
    assert cfg.adc_start_time_s + cfg.n_samples / cfg.adc_rate_sps <= cfg.ramp_end_time_s
    assert cfg.start_freq_hz + cfg.slope_hz_per_s * cfg.ramp_end_time_s <= 81e9
    assert cfg.max_beat_frequency_hz <= 15e6


def test_limits_are_inclusive_at_the_boundary():
    """Exactly 37.5 Msps is allowed by the ADC check (the IF check then binds at 30 Msps),
    and an ADC window ending exactly at the ramp end is allowed."""
    RadarConfig.from_fields(adc_rate_sps=30e6)
    with pytest.raises(ValueError, match="IF"):
        RadarConfig.from_fields(adc_rate_sps=37.5e6)
    # 5 us + 384 / 30 Msps = 17.8 us: set the ramp end there (chirp period follows).
    RadarConfig.from_fields(ramp_end_time_s=17.8e-6, chirp_period_s=22.8e-6)
    with pytest.raises(ValueError, match="n_samples=384"):
        RadarConfig.from_fields(ramp_end_time_s=17.7e-6, chirp_period_s=22.7e-6)


def test_default_subbands_follow_empty_band_rule():
    """[TI-DDMA] 3.3: N = Nt + 2 for Nt = 4, Nt + 1 otherwise; Tx order restricted to active Tx."""
    assert RadarConfig.from_fields(n_tx=4).n_subbands == 6
    cfg3 = RadarConfig.from_fields(n_tx=3)
    assert cfg3.n_subbands == 4 and cfg3.tx_order == (1, 3, 2)
    assert RadarConfig.from_fields(n_tx=2).n_subbands == 3
    assert RadarConfig.from_fields(n_tx=1).n_subbands == 2


# ----------------------------------------------------------------------------- (de)serialisation
def test_dict_round_trip_and_unknown_keys(make_config):
    cfg = make_config(tx_phase_error_deg=(1.0, -2.0, 3.0, 0.5), phase_quantization="round")
    data = cfg.to_dict()
    assert isinstance(data["tx_order"], list)
    assert RadarConfig.from_dict(data) == cfg
    with pytest.raises(ValueError, match=r"unknown RadarConfig field\(s\) \['slope_mhz_per_us'\]"):
        RadarConfig.from_dict({**data, "slope_mhz_per_us": 8.883})


def test_replace_validates_and_rejects_unknown_fields(make_config):
    cfg = make_config()
    assert cfg.replace(n_rx=2).n_virtual == 8
    with pytest.raises(ValueError, match="unknown RadarConfig field"):
        cfg.replace(n_antennas=3)
    with pytest.raises(ValueError, match="n_chirps=770"):
        cfg.replace(n_chirps=770)
    # Changing n_tx re-derives the Tx order, sub-bands and per-Tx error tuples.
    cfg2 = cfg.replace(n_tx=2)
    assert cfg2.tx_order == (1, 2) and cfg2.n_subbands == 3
    assert cfg2.tx_phase_error_deg == (0.0, 0.0)


def test_config_is_frozen(make_config):
    cfg = make_config()
    with pytest.raises(AttributeError):
        cfg.n_tx = 3  # type: ignore[misc]


@pytest.mark.parametrize("scheme", sorted(radarsim.MIMO_SCHEMES))
def test_hash_is_computed_once_and_left_out_of_the_pickle(scheme):
    """Equal configurations hash alike, the hash is kept on the instance, and a pickled copy
    (a sweep worker's) carries no hash of this process: it hashes again where it lands."""
    cfg = radarsim.presets.r79(scheme)
    other = radarsim.presets.r79(scheme)
    assert cfg == other and cfg is not other and hash(cfg) == hash(other)
    assert cfg.__dict__["_hash"] == hash(cfg)
    assert hash(cfg) == hash(tuple(getattr(cfg, f.name) for f in dataclasses.fields(cfg)))
    state = cfg.__reduce_ex__(pickle.HIGHEST_PROTOCOL)[2]
    assert "_hash" not in state
    back = pickle.loads(pickle.dumps(cfg))
    assert back == cfg and "_hash" not in back.__dict__ and hash(back) == hash(cfg)
    assert "_hash" not in copy.deepcopy(cfg).__dict__
    changed = cfg.replace_fields(n_chirps=cfg.n_chirps // 2)
    assert changed != cfg and "_hash" not in changed.__dict__


def test_a_hash_taken_while_building_is_dropped_when_a_field_is_resolved(monkeypatch):
    """`_set` resolves fields after `__post_init__` may have hashed the instance (a cached
    helper keyed by the configuration): the hash of the finished configuration is that of
    its final parts."""
    seen = []
    real = RadarConfig._set

    def hashing_set(self, **fields):
        seen.append(hash(self))
        real(self, **fields)
    monkeypatch.setattr(RadarConfig, "_set", hashing_set)
    cfg = radarsim.presets.r79("ddma")
    monkeypatch.undo()
    assert seen
    assert hash(cfg) == hash(tuple(getattr(cfg, f.name) for f in dataclasses.fields(cfg)))
    assert hash(cfg) == hash(radarsim.presets.r79("ddma"))


def test_mimo_registry():
    assert {"ddma", "tdma"} <= set(radarsim.MIMO_SCHEMES)


def test_ideal_phase_steps_follow_the_subband_order(make_config):
    """design.md 4.3: Tx k in sub-band p of N = 6 steps 2 pi p / N per chirp; order Tx1, Tx3, Tx4,
    Tx2 gives Tx1 0, Tx2 180, Tx3 60, Tx4 120 deg."""
    np.testing.assert_allclose(np.degrees(make_config().ideal_phase_step_rad()),
                               [0.0, 180.0, 60.0, 120.0])
