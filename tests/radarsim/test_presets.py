"""Presets: the TI R79 DDMA demo waveform ([TI-DDMA] table 2) and its TDMA baseline."""
from __future__ import annotations

import pytest

import radarsim
from radarsim.presets import PRESETS, r79_ddma, r79_tdma


def test_r79_ddma_matches_seed_table_2():
    """[TI-DDMA] table 2 / design.md 4.1."""
    cfg = r79_ddma()
    assert cfg.mimo == "ddma"
    assert (cfg.n_tx, cfg.n_rx) == (4, 4)
    assert cfg.idle_time_s == pytest.approx(5e-6)
    assert cfg.adc_start_time_s == pytest.approx(5e-6)
    assert cfg.ramp_end_time_s == pytest.approx(18.81e-6)
    assert cfg.chirp_period_s == pytest.approx(23.81e-6)
    assert cfg.slope_hz_per_s == pytest.approx(8.883e12)
    assert cfg.n_samples == 384
    assert cfg.adc_rate_sps == pytest.approx(30e6)
    assert cfg.n_chirps == 768
    assert cfg.start_freq_hz == pytest.approx(77e9)
    assert cfg.tx_order == (1, 3, 4, 2)
    assert cfg.n_subbands == 6
    assert cfg.phase_shifter_bits == 6
    assert cfg.phase_quantization == "floor"
    assert cfg.tx_phase_error_deg == (0.0,) * 4 and cfg.tx_gain_error_db == (0.0,) * 4
    assert cfg.phase_noise_deg_rms == 0.0


def test_r79_tdma_same_chirps_and_frame_time():
    """Same chirp count and frame time, one Tx per chirp in turn (Tx1, Tx3, Tx4, Tx2)."""
    ddma, tdma = r79_ddma(), r79_tdma()
    assert tdma.mimo == "tdma"
    assert tdma.n_chirps == ddma.n_chirps
    assert tdma.frame_time_s == pytest.approx(ddma.frame_time_s)
    assert tdma.tx_order == (1, 3, 4, 2)
    # Everything but the scheme is identical.
    assert tdma.replace(mimo="ddma") == ddma


def test_registry_and_overrides():
    assert PRESETS == {"r79_ddma": r79_ddma, "r79_tdma": r79_tdma}
    assert radarsim.presets.PRESETS["r79_tdma"]().mimo == "tdma"
    cfg = r79_ddma(phase_quantization="round", n_rx=2)
    assert cfg.phase_quantization == "round" and cfg.n_rx == 2
    with pytest.raises(ValueError, match="unknown RadarConfig field"):
        r79_ddma(bogus_field=1)
    with pytest.raises(ValueError, match="n_chirps=100"):
        r79_tdma(n_chirps=100, mimo="ddma")
