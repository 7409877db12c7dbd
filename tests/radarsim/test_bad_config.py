"""Bad configuration values: every kind raises ValueError naming the field and the value.

RadarConfig rejects non-numeric and physically absurd RF budgets instead of
overflowing later (5000 dBm Tx power, 1e4 dB noise figure, 1000 dB gain error);
ProcessingConfig never keeps a stale OS rank when the CFAR window changes, never blames a field
the user did not set, and a CFAR window wider than the Doppler axis is refused by name; the
association and saturation settings are checked too.
"""
from __future__ import annotations

import numpy as np
import pytest

import pipeline
import radarsim
from metrics.association import AssociationConfig
from pipeline import ProcessingConfig

R79 = radarsim.presets.r79

RADAR_CASES = {
    "tx_power_5000_dbm": (dict(tx_power_dbm=5000.0), r"tx_power_dbm=5000\.0 is outside"),
    "tx_power_string": (dict(tx_power_dbm="12 dBm"), r"tx_power_dbm='12 dBm' must be a number"),
    "tx_power_bool": (dict(tx_power_dbm=True), r"tx_power_dbm=True must be a number"),
    "noise_figure_1e4_db": (dict(noise_figure_db=1e4), r"noise_figure_db=10000\.0 is outside"),
    "noise_figure_string": (dict(noise_figure_db="low"), r"noise_figure_db='low' must be"),
    "antenna_gain_1000_dbi": (dict(tx_antenna_gain_dbi=1000.0),
                              r"tx_antenna_gain_dbi=1000\.0 is outside"),
    "system_loss_1e3_db": (dict(system_loss_db=1e3), r"system_loss_db=1000\.0 is outside"),
    "adc_full_scale_1e6_dbm": (dict(adc_full_scale_dbm=1e6),
                               r"adc_full_scale_dbm=1000000\.0 is outside"),
    "temperature_1e6_k": (dict(temperature_k=1e6), r"temperature_k=1000000\.0 is outside"),
    "phase_noise_1e3_deg": (dict(phase_noise_deg_rms=1e3), r"phase_noise_deg_rms=1000\.0"),
    "gain_error_1000_db": (dict(tx_gain_error_db=(1000.0, 0.0, 0.0, 0.0)),
                           r"tx_gain_error_db=\(1000\.0, 0\.0, 0\.0, 0\.0\) must be"),
    "gain_error_string": (dict(tx_gain_error_db="abcd"), r"tx_gain_error_db='abcd' must be"),
    "phase_error_1e4_deg": (dict(tx_phase_error_deg=(1e4, 0.0, 0.0, 0.0)),
                            r"tx_phase_error_deg=\(10000\.0, 0\.0, 0\.0, 0\.0\) must be"),
    "rx_gain_error_1000_db": (dict(rx_gain_error_db=(1000.0, 0.0, 0.0, 0.0)),
                              r"rx_gain_error_db=\(1000\.0, 0\.0, 0\.0, 0\.0\) must be"),
    "rx_phase_error_nan": (dict(rx_phase_error_deg=(float("nan"), 0.0, 0.0, 0.0)),
                           r"rx_phase_error_deg=\(nan, 0\.0, 0\.0, 0\.0\) must be"),
    "rx_phase_error_3_of_4": (dict(rx_phase_error_deg=(0.0, 1.0, 2.0)),
                              r"rx_phase_error_deg must hold 4 finite values"),
    "range_bias_100_m": (dict(range_bias_m=100.0),
                         r"range_bias_m=100\.0 must be finite and within \+/-10 m"),
    "range_bias_inf": (dict(range_bias_m=float("inf")), r"range_bias_m=inf must be finite"),
    "n_chirps_string": (dict(n_chirps="768"), r"n_chirps='768' must be a number"),
    "adc_rate_over_chip": (dict(adc_rate_sps=50e6), r"adc_rate_sps=5e\+07 exceeds"),
}


@pytest.mark.parametrize("overrides, match", list(RADAR_CASES.values()), ids=list(RADAR_CASES))
def test_radar_config_rejects(overrides, match):
    with pytest.raises(ValueError, match=match):
        R79("ddma", **overrides)


def test_plausible_rf_budget_still_accepted():
    cfg = R79("ddma", tx_power_dbm=13.0, noise_figure_db=14.0, tx_gain_error_db=(0, -1, 1, 0))
    assert cfg.tx_power_dbm == 13.0


# ------------------------------------------------------------------------- processing config
def test_window_change_rederives_a_default_os_rank():
    p = ProcessingConfig().replace(cfar_window_cells=4)
    assert (p.cfar.window_cells, p.cfar.os_rank) == (4, 6)  # round(3/4 x 8), not the stale 18
    assert ProcessingConfig().replace(cfar_window_cells=16).cfar.os_rank == 24


def test_window_change_never_keeps_an_explicit_rank_silently():
    p = ProcessingConfig().replace(cfar_os_rank=20)
    with pytest.raises(ValueError, match=r"cfar_window_cells=4 changes the training window, but "
                                         r"os_rank=20 was chosen for window_cells=12"):
        p.replace(cfar_window_cells=4)
    assert p.replace(cfar_window_cells=4, cfar_os_rank=5).cfar.os_rank == 5


PROCESSING_CASES = {
    "unknown_cfar_field": (dict(cfar_bogus=1), r"unknown CfarConfig field\(s\) \['cfar_bogus'\]"),
    "unknown_field": (dict(bogus=1), r"unknown ProcessingConfig field\(s\) \['bogus'\]"),
    "os_rank_string": (dict(cfar_os_rank="k"), r"os_rank='k' must be"),
    "saturation_policy": (dict(saturation_policy="ignore"),
                          r"saturation_policy='ignore' is not one of \['drop', 'flag'\]"),
}


@pytest.mark.parametrize("changes, match", list(PROCESSING_CASES.values()),
                         ids=list(PROCESSING_CASES))
def test_processing_config_rejects(changes, match):
    with pytest.raises(ValueError, match=match):
        ProcessingConfig().replace(**changes)


@pytest.mark.parametrize("mimo, n_dop", [("ddma", 128), ("tdma", 192)])
def test_cfar_window_wider_than_the_doppler_axis_is_refused_by_name(mimo, n_dop):
    cfg = R79(mimo)
    assert cfg.n_doppler_bins == n_dop
    proc = ProcessingConfig().replace(cfar_window_cells=n_dop)
    adc = np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.int16)
    with pytest.raises(ValueError, match=rf"cfar window_cells={n_dop} .* more than the {n_dop} "
                                         r"bins of the radar's Doppler axis"):
        pipeline.process_frame(cfg, adc, proc)


def test_association_config_rejects_a_non_bool_rule():
    with pytest.raises(ValueError, match=r"require_scatterer='yes' must be true or false"):
        AssociationConfig(require_scatterer="yes")


#: Kinds of bad input in this module (tally for the issue's closing note).
N_KINDS = len(RADAR_CASES) + len(PROCESSING_CASES) + 2 + 2 + 1
