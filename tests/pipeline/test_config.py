"""Validation of the processing configuration: one test per rule."""
import pytest

from pipeline import CfarConfig, ProcessingConfig


def test_defaults_derive_os_rank_and_threshold():
    cf = CfarConfig()
    assert cf.os_rank == round(0.75 * 2 * cf.window_cells)
    assert cf.scale() == pytest.approx(16.29, abs=5e-3)  # N=24, k=18, Pfa=1e-6 (Rohling)
    assert CfarConfig(threshold_db=10.0).scale() == pytest.approx(10.0)


@pytest.mark.parametrize("kwargs, match", [
    ({"mode": "median"}, "cfar mode"),
    ({"guard_cells": -1}, "guard_cells"),
    ({"window_cells": 0}, "window_cells"),
    ({"training_stride": 0}, "training_stride"),
    ({"os_rank": 25}, "os_rank"),
    ({"pfa": 0.0}, "pfa"),
    ({"pfa": None}, "pfa"),
    ({"threshold_db": float("nan")}, "threshold_db"),
])
def test_cfar_config_rules(kwargs, match):
    with pytest.raises(ValueError, match=match):
        CfarConfig(**kwargs)


@pytest.mark.parametrize("kwargs, match", [
    ({"cfar": "os"}, "cfar must be a CfarConfig"),
    ({"range_window": "kaiser"}, "range_window"),
    ({"doppler_window": "gauss"}, "doppler_window"),
    ({"n_azimuth_bins": 8}, "n_azimuth_bins"),
    ({"min_range_bin": -1}, "min_range_bin"),
    ({"azimuth_sidelobe_db": 0.0}, "azimuth_sidelobe_db"),
])
def test_processing_config_rules(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ProcessingConfig().replace(**kwargs)


def test_replace_reaches_cfar_fields_and_rejects_unknown():
    proc = ProcessingConfig().replace(cfar_pfa=1e-4, tdma_disambiguation=False)
    assert proc.cfar.pfa == 1e-4 and not proc.velocity.tdma_disambiguation
    with pytest.raises(ValueError, match="unknown ProcessingConfig"):
        ProcessingConfig().replace(colour="red")


def test_unmitigated_turns_only_the_repair_off():
    proc = ProcessingConfig().replace(**{"interference.magdiff_snr_db": 20.0, "cfar.pfa": 1e-5})
    off = proc.unmitigated
    assert not off.interference.enabled and off.interference.magdiff_snr_db == 20.0
    assert off.replace(**{"interference.repair": proc.interference.repair}) == proc
    assert off.unmitigated == off  # already off: the same settings
