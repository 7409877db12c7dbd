"""The MIMO scheme registry: presets, transmit codes, promises, validation rules, TI mapping."""
import numpy as np
import pytest

import radarsim
from radarsim import RadarConfig
from radarsim.mimo import MIMO_SCHEMES, TdmaScheme, hadamard, register_scheme, scheme_of
from radarsim.ti import from_ti_cfg, to_ti_cfg

REGISTRY = sorted(MIMO_SCHEMES)


def test_registry_holds_the_contract_schemes():
    assert {"ddma", "tdma", "bpm", "ddma_classic"} <= set(radarsim.MIMO_SCHEMES)
    assert all(MIMO_SCHEMES[n].name == n for n in MIMO_SCHEMES)


@pytest.mark.parametrize("name", REGISTRY)
def test_r79_preset_of_every_scheme(name):
    """[TI-DDMA] table 2 timing for every scheme: 768 chirps of 23.81 us, 4 Tx, 4 Rx."""
    cfg = radarsim.presets.r79(name)
    assert (cfg.mimo, cfg.n_chirps, cfg.n_tx, cfg.n_rx) == (name, 768, 4, 4)
    assert cfg.chirp_period_s == pytest.approx(23.81e-6)
    assert cfg.frame_time_s == pytest.approx(18.29e-3, abs=1e-5)
    assert radarsim.presets.r79(name, noise_figure_db=14.0).noise_figure_db == 14.0


def test_r79_ddma_and_tdma_are_the_registry_presets():
    assert radarsim.presets.r79_ddma() == radarsim.presets.r79("ddma")
    assert radarsim.presets.r79_tdma() == radarsim.presets.r79("tdma")
    with pytest.raises(ValueError, match=r"mimo='nope' is not one of"):
        radarsim.presets.r79("nope")


@pytest.mark.parametrize("name, vmax, step", [
    ("ddma", 40.88, 13.63),          # lambda / (4 Tc); one of 6 sub-bands (design.md 8)
    ("ddma_classic", 40.88, 20.44),  # one of 4 sub-bands
    ("tdma", 10.22, 20.44),          # lambda / (16 Tc); 2 Vmax
    ("bpm", 10.22, 20.44),           # lambda / (4 Nt Tc), as TDMA
])
def test_unambiguous_velocity_and_failure_step(name, vmax, step):
    cfg = radarsim.presets.r79(name)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(vmax, abs=0.01)
    assert cfg.scheme.velocity_failure_step_mps(cfg) == pytest.approx(step, abs=0.01)


@pytest.mark.parametrize("name", REGISTRY)
def test_transmit_code_shape_and_energy(name):
    """(n_tx, n_chirps) weights; |w| is 0 or 1 (before shifter errors); every Tx transmits
    the same number of chirps; the frontend's phasors are the code when there are no errors."""
    cfg = radarsim.presets.r79(name)
    code = cfg.scheme.transmit_code(cfg)
    w = code.weights
    assert w.shape == (cfg.n_tx, cfg.n_chirps)
    assert np.all(np.isin(np.round(np.abs(w), 12), (0.0, 1.0)))
    energy = (np.abs(w) ** 2).sum(axis=1)
    assert np.all(energy == energy[0])
    np.testing.assert_allclose(radarsim.transmit_phasors(cfg), w, atol=1e-12)


@pytest.mark.parametrize("n_tx", [1, 2, 4])
def test_bpm_code_is_a_hadamard_matrix(n_tx):
    """H H^T = Nt I; the 2-Tx code is TI's BPM demo: Tx1 (+, +), Tx2 (+, -)."""
    h = hadamard(n_tx)
    np.testing.assert_array_equal(h @ h.T, n_tx * np.eye(n_tx))
    cfg = radarsim.presets.r79("bpm", n_tx=n_tx)
    g = cfg.scheme.transmit_code(cfg).gain
    np.testing.assert_array_equal(g @ g.T, cfg.n_chirps * np.eye(n_tx))
    if n_tx == 2:
        np.testing.assert_array_equal(g[:, :2], [[1, 1], [1, -1]])


def test_classic_ddma_steps_are_quarter_turns():
    """N = Nt = 4: Tx p steps 2 pi p / 4, exact 6-bit codes (90 deg = 16 LSB), no empty band."""
    cfg = radarsim.presets.r79("ddma_classic")
    assert cfg.n_subbands == 4 and cfg.tx_order == (1, 2, 3, 4)
    assert cfg.n_doppler_bins == 192
    step = np.angle(np.exp(1j * np.diff(cfg.applied_phase_rad(), axis=1)), deg=True)
    np.testing.assert_allclose(np.mod(step[:, 0], 360), [0, 90, 180, 270], atol=1e-9)


def test_changing_mimo_rederives_the_scheme_defaults():
    cfg = radarsim.presets.r79("ddma").replace(mimo="ddma_classic")
    assert cfg.n_subbands == 4 and cfg.tx_order == (1, 2, 3, 4)
    assert radarsim.presets.r79("ddma_classic").replace(mimo="ddma").n_subbands == 6


@pytest.mark.parametrize("kw, match", [
    (dict(mimo="ddma", n_subbands=4), r"n_subbands=4 must be an integer > n_tx=4"),
    (dict(mimo="ddma", n_chirps=770), r"n_chirps=770 must be divisible .* n_subbands=6"),
    (dict(mimo="ddma_classic", n_subbands=6), r"n_subbands=6 must equal n_tx=4"),
    (dict(mimo="ddma_classic", n_chirps=770), r"n_chirps=770 .* n_subbands=4"),
    (dict(mimo="tdma", n_chirps=770), r"n_chirps=770 must be divisible by n_tx=4 for TDMA"),
    (dict(mimo="bpm", n_tx=3, n_chirps=768), r"n_tx=3 must be a power of 2"),
    (dict(mimo="bpm", n_chirps=770), r"n_chirps=770 .* n_tx=4 for BPM"),
    (dict(mimo="fdma"), r"mimo='fdma' is not one of"),
    (dict(mimo="ddma", n_subbands=0), r"n_subbands=0 must be an integer >= 1"),
], ids=["ddma_subbands", "ddma_chirps", "classic_subbands", "classic_chirps", "tdma_chirps",
        "bpm_power_of_two", "bpm_chirps", "unknown", "subbands_positive"])
def test_scheme_validation_rules(kw, match):
    with pytest.raises(ValueError, match=match):
        RadarConfig.from_fields(**kw)


def test_register_scheme_rules():
    with pytest.raises(ValueError, match=r"name='tdma' is already registered"):
        register_scheme(TdmaScheme("tdma", "again"))
    with pytest.raises(ValueError, match=r"must be a non-empty identifier"):
        register_scheme(TdmaScheme("no way", "x"))
    with pytest.raises(ValueError, match="must be a MimoScheme"):
        register_scheme("tdma")
    assert scheme_of("tdma") is MIMO_SCHEMES["tdma"]


@pytest.mark.parametrize("name", REGISTRY)
def test_ti_cli_round_trip_or_named_refusal(name):
    """Each scheme maps itself to and from the TI CLI (chirpCfg/frameCfg loop,
    ddmPhaseShiftAntOrder); 4-Tx BPM has none (bpmCfg of the xwr16xx SDK drives 2 Tx)."""
    cfg = radarsim.presets.r79(name)
    try:
        text = to_ti_cfg(cfg)
    except ValueError as exc:
        assert "has no TI mmWave SDK CLI form" in str(exc)
        return
    assert from_ti_cfg(text) == cfg


def _tx_phases(cfg, sin_az):
    """(n_tx,) phase of each Tx in `tx_order` towards azimuth asin(sin_az), elevation 0."""
    pos = cfg.tx_positions_m[np.array(cfg.tx_order) - 1]
    return np.exp(2j * np.pi / cfg.wavelength_m * pos[:, 1] * sin_az)


def test_bpm_code_spreads_a_boresight_echo_over_the_block():
    """The 4-Tx code's rows all have odd parity (the Sylvester rows negated in Tx3's column):
    a boresight echo's transmit superposition C e, e = (1, 1, 1, 1), lands on every chirp of
    the block (|C e| = 2 each; Sylvester: 4, 0, 0, 0, so one chirp per block and every
    velocity hypothesis alike), and the wrong hypothesis two slots apart (per-chirp residual
    (1, -1, 1, -1)) decodes the boresight array to a signed permutation that is no plane wave."""
    cfg = radarsim.presets.r79("bpm")
    c = cfg.scheme.code_matrix(cfg)
    np.testing.assert_array_equal(c @ c.T, 4 * np.eye(4))
    assert np.all(np.prod(c, axis=1) == -1)
    e0 = _tx_phases(cfg, 0.0)
    np.testing.assert_allclose(np.abs(c @ e0), [2, 2, 2, 2], atol=1e-9)
    np.testing.assert_allclose(np.abs(hadamard(4) @ e0), [4, 0, 0, 0], atol=1e-9)
    m = c.T @ np.diag([1, -1, 1, -1]) @ c / 4
    assert np.all(np.isin(np.abs(m), (0, 1))) and not np.allclose(m @ e0, e0) \
        and not np.allclose(m @ e0, -e0)


def test_bpm_code_blind_azimuth_is_the_documented_one():
    """`BpmScheme`'s limit: at sin(az) = 1/2 (30 deg, elevation 0) the R79 Tx phases are
    (1, 1, 1, -1) in tx_order (Tx1, Tx3, Tx4 four elements apart, Tx2 two), proportional to
    a row of the code: the echo sits in one chirp of each block."""
    cfg = radarsim.presets.r79("bpm")
    c = cfg.scheme.code_matrix(cfg)
    e = _tx_phases(cfg, 0.5)
    np.testing.assert_allclose(e, [1, 1, 1, -1], atol=1e-9)
    np.testing.assert_allclose(np.sort(np.abs(c @ e)), [0, 0, 0, 4], atol=1e-9)


def test_velocity_blind_directions():
    """TDMA resolves every direction; BPM flags the band where one chirp carries >= 90 % of
    the echo (28-32 deg at elevation 0: +/-2 deg around the blind 30 deg), both signs, and
    not boresight; angles broadcast."""
    tdma, bpm = radarsim.presets.r79("tdma"), radarsim.presets.r79("bpm")
    az = np.array([0.0, 2.0, 27.0, 28.0, 30.0, 32.0, 33.0, -30.0])
    assert not tdma.scheme.velocity_blind(tdma, az).any()
    np.testing.assert_array_equal(bpm.scheme.velocity_blind(bpm, az),
                                  [False, False, False, True, True, True, False, True])
    assert bpm.scheme.velocity_blind(bpm, 30.0, np.zeros((2, 3))).shape == (2, 3)
