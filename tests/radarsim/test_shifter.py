"""Per-code shifter errors, Tx coupling and calibration ([TI-DDMA] section 4.2).

Analytic references: a transmit sequence periodic in P chirps has a line spectrum whose
complex amplitudes are the DFT of one period's weights (Oppenheim & Schafer 8.1; design.md 8
"spur of a code-periodic transmit error"); the 6-bit floor-quantisation spur of the R79 codes is
-34.5 dBc for the 60/120-deg-step Tx and absent for 0 and 180 deg (design.md 8); a noiseless
measurement recovers the table exactly and the residual is the rounding to the (perturbed)
code grid.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import radarsim
from harness.shifter_experiment import line_spectrum, phase_step_experiment
from radarsim import shifter as sh
from radarsim.calibration import resolve_calibration, shifter_phase_residual_deg
from radarsim.config import RadarConfig

N_CODES = 64
LSB = 5.625


def _table(rms, seed, dist="gaussian", n_tx=4):
    return sh.ShifterErrorSpec(distribution=dist, rms=rms, seed=seed).draw(n_tx, N_CODES)


def _reflector(range_m=4.5, rcs_m2=10.0):
    return radarsim.Scatterers(position_m=[[range_m, 0.0, 0.0]],
                               velocity_mps=[[0.0, 0.0, 0.0]], rcs_m2=[rcs_m2])


# ----------------------------------------------------------------------------- error tables
@pytest.mark.parametrize("dist", sorted(sh.SHIFTER_ERROR_DISTRIBUTIONS))
def test_drawn_tables_have_exact_rms_zero_code_0_and_are_seeded(dist):
    t = _table(5.0, 3, dist)
    assert t.shape == (4, N_CODES)
    np.testing.assert_allclose(np.sqrt(np.mean(t ** 2, axis=1)), 5.0, rtol=1e-12)
    assert np.all(t[:, 0] == 0)
    np.testing.assert_array_equal(t, _table(5.0, 3, dist))
    assert not np.array_equal(t, _table(5.0, 4, dist))
    assert np.all(_table(0.0, 3, dist) == 0)


def test_inl_dnl_curve_is_smoother_than_independent_errors():
    """The INL part is a sum of low harmonics: code-to-code steps are far smaller than for
    independent per-code errors of the same rms (whose step rms is sqrt(2) x rms). Expected
    ratio: the white DNL share f = 0.2 steps by sqrt(2 f) = 0.63 rms, the harmonics h = 1..3
    over 64 codes by about 2 pi / 64 x 1.2 = 0.12 rms, so sqrt(0.63^2 + 0.8 x 0.12^2) / sqrt(2)
    = 0.45; the bound 0.6 leaves three standard deviations of an rms over 4 x 63 steps."""
    smooth = _table(5.0, 0, "inl_dnl")
    white = _table(5.0, 0, "gaussian")
    step = lambda t: np.sqrt(np.mean(np.diff(t, axis=1) ** 2))  # noqa: E731
    assert step(smooth) < 0.6 * step(white)


def test_config_accepts_spec_mapping_and_round_trips(make_config):
    cfg = make_config(shifter_phase_error_deg={"distribution": "inl_dnl", "rms": 6.0, "seed": 1},
                      shifter_gain_error_db={"distribution": "uniform", "rms": 0.2, "seed": 2})
    np.testing.assert_array_equal(np.asarray(cfg.shifter_phase_error_deg),
                                  sh.ShifterErrorSpec(distribution="inl_dnl", rms=6.0,
                                                      seed=1).draw(4, N_CODES))
    data = cfg.to_dict()
    assert len(data["shifter_phase_error_deg"]) == 4
    assert RadarConfig.from_dict(data) == cfg
    hash(cfg)  # the chain caches on the config
    # Programmed codes are unchanged by the hardware tables (no calibration).
    np.testing.assert_array_equal(cfg.phase_codes(), make_config().phase_codes())


def test_design_8_quantisation_spur_of_r79_codes(make_config):
    """design.md 8: floor-quantised R79 codes, ideal shifter: -34.5 dBc spur for the 60/120-deg
    Tx (Tx3, Tx4), no spur for 0 (Tx1) and 180 deg (Tx2)."""
    cfg = make_config()
    w = radarsim.transmit_phasors(cfg)[:, :cfg.n_subbands]
    lv = sh.spur_levels_dbc(w)
    lv_sorted = np.sort(lv, axis=1)
    assert lv_sorted[2, -2] == pytest.approx(-34.5, abs=0.3)
    assert lv_sorted[3, -2] == pytest.approx(-34.5, abs=0.3)
    assert lv_sorted[0, -2] < -200 and lv_sorted[1, -2] < -200


# ----------------------------------------------------------------------------- analytic spurs
def _measured_lines_dbc(adc, period):
    _, p = line_spectrum(adc)
    bins = np.arange(period) * (len(p) // period)
    return 10 * np.log10(p[bins] / p[bins].max()), p


def _assert_lines_match(measured, predicted, power):
    """Lines well above the noise floor within 1 dB; predicted-zero lines at the floor."""
    floor_dbc = 10 * np.log10(np.median(power) / power.max())
    strong = predicted > floor_dbc + 25
    assert strong[np.argmax(predicted)]
    np.testing.assert_allclose(measured[strong], predicted[strong], atol=1.0)
    assert np.all(measured[predicted < floor_dbc - 20] < floor_dbc + 12)


def test_90_degree_step_lines_match_dft_of_code_period(make_config):
    """[TI-DDMA] figs 7-8 set-up with a random per-code table: every line (target, mirror
    ghost, DC and Nyquist spurs) within 1 dB of the DFT of the 4-chirp code period."""
    cfg = make_config(phase_quantization="round", shifter_phase_error_deg=_table(6.0, 11),
                      shifter_gain_error_db=_table(0.3, 12))
    res = phase_step_experiment(cfg, rng=np.random.default_rng(0), n_chirps=512)
    lines = res.lines
    assert list(res.codes) == [0, 16, 32, 48]
    assert lines.loc[lines["role"] == "target", "velocity_over_vmax"].item() == 0.5
    assert lines.loc[lines["role"] == "mirror ghost", "velocity_over_vmax"].item() == -0.5
    np.testing.assert_allclose(lines["measured_dbc"], lines["predicted_dbc"], atol=1.0)
    assert lines["predicted_dbc"].nlargest(2).iloc[1] > -60  # spurs well above the floor


@pytest.mark.parametrize("tx", [1, 2, 3, 4], ids=lambda t: f"Tx{t}")
def test_r79_empty_band_lines_match_dft_every_tx_every_subband(make_config, tx):
    """R79 empty-band codes with a random per-code table: Tx alone, its Doppler lines at every
    sub-band offset (m x 128 bins) within 1 dB of the DFT of its 6-chirp code period."""
    cfg = make_config(shifter_phase_error_deg=_table(5.0, 21),
                      shifter_gain_error_db=_table(0.3, 22))
    w = radarsim.transmit_phasors(cfg)
    w_alone = np.zeros_like(w)
    w_alone[tx - 1] = w[tx - 1]
    adc = radarsim.simulate_frame_weights(cfg, _reflector(), np.random.default_rng(tx), w_alone)
    measured, power = _measured_lines_dbc(adc, cfg.n_subbands)
    predicted = sh.spur_levels_dbc(w[tx - 1, :cfg.n_subbands])
    _assert_lines_match(measured, predicted, power)


# ----------------------------------------------------------------------------- coupling
def test_identity_coupling_is_bit_identical_to_no_coupling(make_config, make_scene,
                                                          monkeypatch):
    scene = make_scene([(30.0, 10.0, 0.0, -5.0, 10.0), (80.0, -30.0, 2.0, 12.0, 3.0)])
    eye_db = np.where(np.eye(4, dtype=bool), 0.0, -np.inf)
    for mimo in ("ddma", "tdma"):
        cfg = make_config(mimo, tx_coupling_db=eye_db, tx_coupling_deg=np.zeros((4, 4)),
                          phase_noise_deg_rms=2.0, tx_phase_error_deg=(1.0, -2.0, 3.0, 0.5))
        with_c = radarsim.simulate_frame(cfg, scene, np.random.default_rng(7))
        monkeypatch.setattr(radarsim.frontend, "apply_coupling", lambda c, w: w)
        without = radarsim.simulate_frame(cfg, scene, np.random.default_rng(7))
        monkeypatch.undo()
        np.testing.assert_array_equal(with_c, without)


def test_coupling_mixes_transmit_weights(make_config):
    """TDMA slot of Tx1 with Tx3 coupled at -20 dB, 30 deg: element 3 radiates 0.1 e^{j30}
    of Tx1's signal, nothing else changes."""
    lvl = np.where(np.eye(4, dtype=bool), 0.0, -np.inf)
    ph = np.zeros((4, 4))
    lvl[2, 0], ph[2, 0] = -20.0, 30.0
    cfg = make_config("tdma", tx_coupling_db=lvl, tx_coupling_deg=ph)
    w = radarsim.transmit_phasors(cfg)
    w0 = radarsim.transmit_phasors(make_config("tdma"))
    np.testing.assert_allclose(w[2, 0], 0.1 * np.exp(1j * np.radians(30.0)) * w0[0, 0])
    np.testing.assert_array_equal(w[[0, 1, 3]], w0[[0, 1, 3]])


# ----------------------------------------------------------------------------- calibration
def test_noiseless_calibration_recovers_table_and_residual_is_grid_rounding(make_config):
    e, g = _table(8.0, 31, "inl_dnl"), _table(0.4, 32)
    e[:, 0], g[:, 0] = 2.0, 0.1  # a code-0 offset is array calibration: measured relative to it
    cfg = make_config(shifter_phase_error_deg=e, shifter_gain_error_db=g)
    meas = radarsim.measure_shifters(cfg, rng=np.random.default_rng(0), thermal_noise=False)
    np.testing.assert_allclose(meas.phase_error_deg, e - e[:, :1], atol=1e-9)
    np.testing.assert_allclose(meas.gain_error_db, g - g[:, :1], atol=1e-9)
    res = radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(0), thermal_noise=False,
                                      full_output=True)
    assert isinstance(res.config, RadarConfig)
    assert res.config.shifter_phase_error_deg == cfg.shifter_phase_error_deg
    assert res.config.shifter_gain_error_db == cfg.shifter_gain_error_db
    # Independent brute force: the best achievable phase on the perturbed code grid.
    wanted = cfg.programmed_phase_deg()
    best = np.empty_like(wanted)
    for k in range(4):
        for p in range(wanted.shape[1]):
            ph = [(q * LSB + e[k, q] - e[k, 0] - wanted[k, p] + 180) % 360 - 180
                  for q in range(N_CODES)]
            best[k, p] = min(ph, key=abs)
    np.testing.assert_allclose(res.residual_deg, best, atol=1e-9)
    assert res.residual_rms_deg == pytest.approx(np.sqrt(np.mean(best ** 2)))
    assert res.residual_max_deg == pytest.approx(np.max(np.abs(best)))
    assert res.residual_max_deg < res.residual_before_max_deg


def test_calibration_of_ideal_shifter_rounds_to_the_nominal_grid(make_config):
    """Zero tables: residual = distance of each wanted phase to the nearest multiple of the
    LSB (R79: 1.875 deg for the 60-deg multiples, 0 for 0/180), i.e. the SDK's round rule."""
    cfg = make_config()
    out = radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(0), thermal_noise=False)
    np.testing.assert_array_equal(out.phase_codes(), make_config(
        phase_quantization="round").phase_codes())
    wanted = cfg.programmed_phase_deg()
    np.testing.assert_allclose(np.abs(shifter_phase_residual_deg(out)),
                               np.abs(wanted - LSB * np.round(wanted / LSB)), atol=1e-9)
    assert np.abs(shifter_phase_residual_deg(out)).max() == pytest.approx(1.875)


def test_noisy_calibration_error_follows_measurement_snr(make_config):
    """Phase-estimate std of a tone in complex noise: 1/sqrt(2 SNR N) rad per code (Kay
    15.13); the ratio to code 0 shares code 0's error, removed by the row mean."""
    cfg = make_config(shifter_phase_error_deg=_table(5.0, 41))
    meas = radarsim.measure_shifters(cfg, rng=np.random.default_rng(3), rcs_m2=1e-4,
                                     n_repeats=4)
    err = meas.phase_error_deg - np.asarray(cfg.shifter_phase_error_deg)
    err = err[:, 1:] - err[:, 1:].mean(axis=1, keepdims=True)
    expect = math.degrees(1 / math.sqrt(2 * 10 ** (meas.snr_db / 10) * 4))
    assert np.std(err) == pytest.approx(expect, rel=0.15)


def test_calibration_request_runs_calibrate_shifters(make_config):
    spec = {"distribution": "inl_dnl", "rms": 10.0, "seed": 5}
    cfg = make_config(shifter_phase_error_deg=spec)
    cal = resolve_calibration(cfg, {"seed": 2})
    direct = radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(2))
    assert cal == direct
    assert resolve_calibration(cfg, None) is cfg
    assert np.sqrt(np.mean(shifter_phase_residual_deg(cal) ** 2)) < \
        np.sqrt(np.mean(shifter_phase_residual_deg(cfg) ** 2))


def test_a_config_never_runs_a_calibration(make_config):
    """A config is a value: a calibration request in it is refused, not measured."""
    with pytest.raises(ValueError, match=r"shifter_calibration_deg=\{'seed': 0\} is a "
                                         r"calibration request, not a measured table"):
        make_config(shifter_calibration_deg={"seed": 0})


_BAD_REQUESTS = [
    ({"seed": -3}, r"shifter_calibration_deg: seed=-3 must be an integer >= 0"),
    ({"seed": 0, "range": 4.5}, r"shifter_calibration_deg: bad calibration spec .*unknown "
                                r"key\(s\) \['range'\]"),
    ({"seed": 0, "range_m": -1.0}, r"shifter_calibration_deg: range_m=-1.0 must be"),
    ([0], r"shifter_calibration_deg: a calibration request is a table"),
]


@pytest.mark.parametrize("request_,match", _BAD_REQUESTS, ids=[m for _, m in _BAD_REQUESTS])
def test_bad_calibration_requests(make_config, request_, match):
    with pytest.raises(ValueError, match=match):
        resolve_calibration(make_config(), request_)


# ----------------------------------------------------------------------------- validation
_BAD = [
    ("shifter_phase_error_deg", np.zeros((4, 32)), r"shifter_phase_error_deg has shape \(4, 32\)"),
    ("shifter_phase_error_deg", np.full((4, 64), np.nan),
     r"shifter_phase_error_deg\[0\]\[0\]=nan must be finite"),
    ("shifter_phase_error_deg", np.full((4, 64), 200.0),
     r"shifter_phase_error_deg\[0\]\[0\]=200.0 exceeds the limit \+/-180"),
    ("shifter_gain_error_db", np.full((4, 64), -12.0),
     r"shifter_gain_error_db\[0\]\[0\]=-12.0 exceeds the limit \+/-10"),
    ("shifter_gain_error_db", {"distribution": "cauchy", "rms": 1.0},
     r"shifter_gain_error_db: distribution='cauchy' is not one of"),
    ("shifter_phase_error_deg", {"distribution": "uniform", "rms": -1.0},
     r"shifter_phase_error_deg: rms=-1.0 must be"),
    ("shifter_phase_error_deg", {"distribution": "uniform", "rms": 1.0, "seed": -1},
     r"seed=-1 must be an integer >= 0"),
    ("shifter_phase_error_deg", {"distribution": "inl_dnl", "rms": 1.0, "dnl_fraction": 2.0},
     r"dnl_fraction=2.0 must be in 0..1"),
    ("shifter_phase_error_deg", {"distribution": "uniform", "rms_deg": 1.0},
     r"shifter_phase_error_deg: bad error-table spec"),
    ("tx_coupling_db", np.zeros((3, 3)), r"tx_coupling_db has shape \(3, 3\), expected \(4, 4\)"),
    ("tx_coupling_db", np.where(np.eye(4), 0.0, np.inf),
     r"tx_coupling_db\[0\]\[1\]=inf must be finite"),
    ("tx_coupling_db", np.where(np.eye(4), 0.0, 3.0),
     r"tx_coupling_db off-diagonal level 3 dB exceeds the limit 0 dB"),
    ("tx_coupling_db", np.where(np.eye(4), -1.0, -30.0), r"diagonal must be 0 dB and 0 deg"),
    ("tx_coupling_deg", np.full((4, 4), np.nan), r"tx_coupling_deg\[0\]\[0\]=nan must be finite"),
    ("shifter_calibration_deg", np.zeros((4, 63)), r"shifter_calibration_deg has shape \(4, 63\)"),
]


@pytest.mark.parametrize("field,value,match", _BAD, ids=[m for _, _, m in _BAD])
def test_validation_rules(make_config, field, value, match):
    with pytest.raises(ValueError, match=match):
        make_config(**{field: value})


def test_calibration_needs_quantised_codes(make_config):
    with pytest.raises(ValueError, match="phase_quantization='none': an ideal shifter"):
        make_config(phase_quantization="none", shifter_calibration_deg=np.zeros((4, 64)))


@pytest.mark.parametrize("kw,match", [({"range_m": 0.0}, "range_m=0.0 must be"),
                                      ({"rcs_m2": -1.0}, "rcs_m2=-1.0 must be > 0"),
                                      ({"n_repeats": 0}, "n_repeats=0 must be an integer")])
def test_calibrate_arguments(make_config, kw, match):
    with pytest.raises(ValueError, match=match):
        radarsim.calibrate_shifters(make_config(), rng=np.random.default_rng(0), **kw)


def test_simulate_frame_weights_shape(make_config):
    with pytest.raises(ValueError, match=r"tx_weights shape \(3, 10\) must be \(n_tx=4"):
        radarsim.simulate_frame_weights(make_config(), _reflector(), np.random.default_rng(0),
                                        np.ones((3, 10), complex))


def test_phase_step_experiment_arguments(make_config):
    with pytest.raises(ValueError, match="step_deg=70.0: 360 / step_deg must be an integer"):
        phase_step_experiment(make_config(), rng=np.random.default_rng(0), step_deg=70.0)


@pytest.mark.parametrize("name", sorted(radarsim.MIMO_SCHEMES))
def test_every_scheme_gets_the_table_and_the_calibration(name):
    """Registry-wide: the shifter factor at each chirp's programmed code multiplies the
    scheme's weights, and calibration never worsens the residual (TDMA, code 0 only: 0)."""
    spec = {"distribution": "inl_dnl", "rms": 10.0, "seed": 3}
    cfg = radarsim.presets.r79(name, shifter_phase_error_deg=spec)
    ideal = radarsim.presets.r79(name)
    codes = radarsim.frontend.programmed_codes(cfg)
    expect = radarsim.transmit_phasors(ideal) * sh.shifter_factor(
        np.asarray(cfg.shifter_phase_error_deg), np.zeros((4, N_CODES)), codes)
    np.testing.assert_allclose(radarsim.transmit_phasors(cfg), expect, atol=1e-12)
    cal = radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(0), thermal_noise=False,
                                      full_output=True)
    assert cal.residual_rms_deg <= cal.residual_before_rms_deg + 1e-12
    w = radarsim.transmit_phasors(cal.config)
    active = np.asarray(ideal.scheme.transmit_code(ideal).gain) != 0
    np.testing.assert_array_equal(np.abs(w) > 0, active)
