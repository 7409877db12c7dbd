"""Radar equipment of road users: the case-file form, the seeded draw, the validation rules."""
from __future__ import annotations

import dataclasses

import pandas as pd
import pytest

import scenarios
from radarsim.interference import EQUIPMENT_COLUMNS
from scenarios.equipment import (
    WAVEFORM_FAMILIES,
    RadarEquipment,
    RadarSpec,
    draw_equipment,
    equipment_table,
)
from scenarios.files import parse_scenario

ACTORS = pd.DataFrame({"actor_id": range(40), "actor_class": ["car", "truck", "motorcycle",
                                                              "bicycle"] * 10,
                       "length_m": 5.0, "width_m": 2.0})


def test_interference_cases_ship_with_the_catalogue():
    names = [n for n in scenarios.SCENARIOS if "interfer" in n]
    assert len(names) >= 3
    ghosts = scenarios.SCENARIOS["interference_same_slope_ghosts"]
    assert dict(ghosts.radars[0].overrides)["slope_hz_per_s"] == 8.883e12
    assert scenarios.SCENARIOS["interference_dense_highway"].equipped_share == 0.5


def test_table_columns_are_what_the_front_end_reads():
    t = equipment_table(ACTORS, 0, equipped_share=1.0)
    assert list(t.columns) == EQUIPMENT_COLUMNS[:1] + [f.name for f in
                                                       dataclasses.fields(RadarEquipment)]
    assert set(EQUIPMENT_COLUMNS) <= set(t.columns)
    assert set(ACTORS.loc[ACTORS.actor_class == "bicycle", "actor_id"]).isdisjoint(t.actor_id)


def test_same_seed_same_radars_and_shares_nest():
    full = equipment_table(ACTORS, 7, equipped_share=1.0)
    pd.testing.assert_frame_equal(full, equipment_table(ACTORS, 7, equipped_share=1.0))
    half = equipment_table(ACTORS, 7, equipped_share=0.5)
    quarter = equipment_table(ACTORS, 7, equipped_share=0.25)
    assert set(quarter.actor_id) <= set(half.actor_id) <= set(full.actor_id)
    pd.testing.assert_frame_equal(half, full[full.actor_id.isin(half.actor_id)]
                                  .reset_index(drop=True))
    assert len(equipment_table(ACTORS, 7, equipped_share=0.0)) == 0
    assert 0.3 < len(half) / len(full) < 0.7


@pytest.mark.parametrize("family", sorted(WAVEFORM_FAMILIES))
def test_drawn_radars_stay_in_their_band(family):
    import numpy as np
    g = np.random.default_rng(0)
    lo, hi = WAVEFORM_FAMILIES[family].band_hz
    for _ in range(50):
        eq = draw_equipment(g, family)
        end = eq.start_freq_hz + eq.slope_hz_per_s * eq.ramp_time_s
        assert lo - 1 <= min(eq.start_freq_hz, end) and max(eq.start_freq_hz, end) <= hi + 1


@pytest.mark.parametrize("kw, match", [
    (dict(slope_hz_per_s=1e11), "slope_hz_per_s"),
    (dict(ramp_time_s=50e-6, chirp_period_s=40e-6), "ramp_time_s"),
    (dict(start_freq_hz=80.9e9), "leaves the 76-81 GHz band"),
    (dict(mount_z_m=0.0), "mount_z_m"),
    (dict(mount_yaw_deg=200.0), "mount_yaw_deg"),
    (dict(tx_power_dbm=30.0), "tx_power_dbm"),
    (dict(antenna_gain_dbi=40.0), "antenna_gain_dbi"),
    (dict(chirp_period_s=0.0), "chirp_period_s"),
    (dict(mount_x_m=float("nan")), "finite"),
])
def test_equipment_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        RadarEquipment(**kw)


def _case(radars):
    return {"name": "x", "description": "d", "mount": "front_left", "duration_s": 1.0,
            "actors": [{"actor_class": "car", "path": "lane_0", "s_m": 20.0}],
            "radars": radars}


@pytest.mark.parametrize("radars, match", [
    ([{"family": "front_lrr"}], r"radars\[0\]\.actor_id: required key missing"),
    ([{"actor_id": 0, "family": "nope"}], "family='nope' unknown"),
    ([{"actor_id": 0, "slope_mhz_per_us": 20.0}],
     r"radars\[0\]\.slope_mhz_per_us: unknown key; known: \["),
    ([{"actor_id": 0, "ramp_time_ms": 0.03}], r"radars\[0\]\.ramp_time_ms: wrong unit; give "
                                              r"radars\[0\]\.ramp_time_s"),
    ([{"actor_id": 0, "tx_power_dbm": 40.0}], "tx_power_dbm"),
    ([{"actor_id": 3}], "not a scripted actor"),
    ({"actor_id": 0}, "array of tables"),
])
def test_case_file_radars_validation(radars, match):
    with pytest.raises(ValueError, match=match):
        parse_scenario(_case(radars))


def test_case_file_radar_spec_round_trip():
    case = parse_scenario(_case([{"actor_id": 0, "family": "corner_srr",
                                  "tx_power_dbm": 10.0}]))
    assert case.radars == (RadarSpec(actor_id=0, family="corner_srr",
                                     overrides=(("tx_power_dbm", 10.0),)),)
    t = equipment_table(pd.DataFrame({"actor_id": [0], "actor_class": ["car"],
                                      "length_m": [5.0], "width_m": [2.0]}), 0,
                        radars=case.radars)
    assert t.loc[0, "tx_power_dbm"] == 10.0 and t.loc[0, "slope_hz_per_s"] != 0
