"""RadarConfig's parts (waveform, array, schedule, shifter, impairments, budget): each checks its
own values; the config reads every field by its own name; dotted keys address them and the
flat keys of the previous release warn with the new key."""
from __future__ import annotations

import dataclasses

import pytest

import radarsim
from core.errors import BadInput
from radarsim.radar_config import FLAT_KEYS, RadarConfig, radar_paths
from radarsim.radar_parts import (
    FIELD_PART,
    PARTS,
    ArrayConfig,
    Impairments,
    MimoSchedule,
    RfBudget,
    ShifterConfig,
    Waveform,
)


@pytest.mark.parametrize("make, match", [
    (lambda: Waveform(n_samples=385), r"n_samples=385 must be even"),
    (lambda: Waveform(adc_mode="complex9x"), r"adc_mode"),
    (lambda: Waveform(slope_hz_per_s=-1.0), r"slope_hz_per_s=-1.0 must be"),
    (lambda: Waveform(adc_start_time_s=-1e-6), r"adc_start_time_s=-1e-06 must be >= 0"),
    (lambda: ArrayConfig(antenna_pattern="dipole"), r"antenna_pattern"),
    (lambda: ArrayConfig(pattern_exponent_az=-1.0), r"pattern_exponent_az=-1.0 must be"),
    (lambda: ArrayConfig(n_tx="4"), r"n_tx='4' must be a number"),
    (lambda: MimoSchedule(mimo="fdma"), r"fdma"),
    (lambda: ShifterConfig(phase_quantization="ceil"), r"phase_quantization"),
    (lambda: Impairments(range_bias_m=11.0), r"range_bias_m=11.0 must be finite and within"),
    (lambda: Impairments(tx_leakage_dbfs=3.0), r"tx_leakage_dbfs=3.0 must be <= 0 dBFS"),
    (lambda: Impairments(tx_gain_error_db=(0.0, 99.0)), r"tx_gain_error_db=.* must be a list"),
    (lambda: Impairments(phase_noise_deg_rms=200.0), r"phase_noise_deg_rms=200.0 is outside"),
    (lambda: RfBudget(tx_power_dbm=100.0), r"tx_power_dbm=100.0 is outside"),
    (lambda: RfBudget(temperature_k=0.0), r"temperature_k=0.0 must be"),
])
def test_each_part_checks_its_own_values(make, match):
    with pytest.raises(BadInput, match=match):
        make()


def test_every_field_is_read_by_its_own_name_from_its_part():
    cfg = radarsim.presets.r79_ddma()
    assert len(FIELD_PART) == 47
    for name, part in FIELD_PART.items():
        assert getattr(cfg, name) is getattr(getattr(cfg, part), name), name


def test_the_flat_names_are_read_only():
    cfg = radarsim.presets.r79_ddma()
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.n_chirps = 256  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.waveform = Waveform()  # type: ignore[misc]


def test_a_config_holds_parts_not_tables():
    with pytest.raises(BadInput, match=r"waveform=\{'n_chirps': 256\} must be a Waveform"):
        RadarConfig(waveform={"n_chirps": 256})


def test_dotted_key_part_table_and_whole_part_give_the_same_config():
    base = radarsim.presets.r79_ddma()
    dotted = base.replace(**{"waveform.n_chirps": 384, "impairments.phase_noise_deg_rms": 2.0})
    table = base.replace(waveform={"n_chirps": 384}, impairments={"phase_noise_deg_rms": 2.0})
    whole = base.replace(waveform=dataclasses.replace(base.waveform, n_chirps=384),
                         impairments=dataclasses.replace(base.impairments,
                                                         phase_noise_deg_rms=2.0))
    assert dotted == table == whole
    assert (dotted.n_chirps, dotted.phase_noise_deg_rms) == (384, 2.0)


def test_a_flat_key_still_works_and_warns_with_the_new_key():
    base = radarsim.presets.r79_ddma()
    with pytest.warns(DeprecationWarning,
                      match=r"'n_chirps' is deprecated: use 'waveform.n_chirps'"):
        old = base.replace(n_chirps=384)
    assert old == base.replace(**{"waveform.n_chirps": 384})
    with pytest.warns(DeprecationWarning, match=r"use 'array.n_rx'"):
        assert radarsim.presets.r79("tdma", n_rx=2).n_virtual == 8


def test_dotted_keys_do_not_warn(recwarn):
    radarsim.presets.r79("tdma", **{"array.n_rx": 2, "schedule.mimo": "bpm"})
    assert not [w for w in recwarn if issubclass(w.category, DeprecationWarning)]


def test_a_changed_field_re_derives_its_followers_across_parts():
    """n_tx lives in the array; the Tx order (schedule) and the per-Tx errors (impairments)
    follow it when not given."""
    cfg = radarsim.presets.r79_ddma().replace(**{"array.n_tx": 3})
    assert cfg.tx_order == (1, 3, 2) and cfg.n_subbands == 4
    assert cfg.tx_phase_error_deg == (0.0, 0.0, 0.0)


def test_a_field_under_another_part_is_refused_naming_the_parts_fields():
    with pytest.raises(BadInput, match=r"unknown RadarConfig field\(s\) \['waveform.n_tx'\]; "
                                       r"waveform holds \["):
        radarsim.presets.r79_ddma().replace(**{"waveform.n_tx": 3})


def test_an_unknown_key_is_refused():
    with pytest.raises(BadInput, match=r"unknown RadarConfig field\(s\) \['slope_mhz_per_us'\]"):
        radarsim.presets.r79_ddma().replace(slope_mhz_per_us=8.0)


def test_radar_paths_and_flat_keys_cover_every_field():
    assert set(FLAT_KEYS) == set(FIELD_PART)
    assert radar_paths({"n_tx": 3}, warn=False) == {"array.n_tx": 3}
    assert set(PARTS) == {"waveform", "array", "schedule", "shifter", "impairments", "budget"}


def test_from_fields_and_to_dict_round_trip_by_field_names():
    cfg = radarsim.presets.r79_tdma()
    assert RadarConfig.from_fields(**{k: getattr(cfg, k) for k in FIELD_PART}) == cfg
    with pytest.raises(BadInput, match=r"unknown RadarConfig field\(s\) \['n_txs'\]"):
        RadarConfig.from_fields(n_txs=3)
