"""Nested processing settings: dotted keys, the flat keys of the previous release (deprecated),
the one interference setting, and caches keyed by the sub-config values."""
from __future__ import annotations

import dataclasses
import warnings

import pytest

import pipeline
from pipeline.chirp_level import noise_floor_key, range_stage_key
from pipeline.config_keys import FLAT_KEYS, dotted_keys
from pipeline.interference import InterferenceConfig

P = pipeline.ProcessingConfig()


def test_at_most_a_dozen_top_level_fields_each_a_frozen_validating_sub_config():
    fields = dataclasses.fields(pipeline.ProcessingConfig)
    assert len(fields) <= 12
    for f in fields:
        value = getattr(P, f.name)
        if dataclasses.is_dataclass(value):
            with pytest.raises(dataclasses.FrozenInstanceError):
                setattr(value, dataclasses.fields(value)[0].name, None)


def test_dotted_keys_and_tables_change_nested_fields():
    assert P.replace(**{"cfar.pfa": 1e-5}).cfar.pfa == 1e-5
    assert P.replace(cfar={"pfa": 1e-5}) == P.replace(**{"cfar.pfa": 1e-5})
    q = P.replace(**{"interference.repair": "ar", "velocity.fast_slow_search_bins": 1})
    assert (q.interference.repair, q.velocity.fast_slow_search_bins) == ("ar", 1)
    assert q.cfar == P.cfar and q.range == P.range


@pytest.mark.parametrize("flat, dotted", sorted(FLAT_KEYS.items()))
def test_every_flat_key_names_an_existing_nested_field(flat, dotted):
    head, _, name = dotted.partition(".")
    assert name in {f.name for f in dataclasses.fields(getattr(P, head))}


def test_a_flat_key_warns_with_the_new_key_and_gives_the_same_config():
    with pytest.warns(DeprecationWarning, match=r"'compression_ratio' is deprecated: use "
                                                r"'compression.ratio'"):
        old = P.replace(compression_ratio=0.4)
    with pytest.warns(DeprecationWarning, match=r"'cfar_pfa' is deprecated: use 'cfar.pfa'"):
        assert P.replace(cfar_pfa=1e-5) == P.replace(**{"cfar.pfa": 1e-5})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert old == P.replace(**{"compression.ratio": 0.4})


def test_interference_switch_and_method_are_one_setting():
    with pytest.warns(DeprecationWarning):
        off = P.replace(interference_mitigation=False)
        on_again = off.replace(interference_mitigation=True)
        zero_off = P.replace(intf_mitigation="zero", interference_mitigation=False)
        zero_on = off.replace(interference_mitigation=True, intf_mitigation="zero")
    assert off.interference.repair == "off" and not off.interference.enabled
    assert on_again.interference == InterferenceConfig()
    assert zero_off.interference.repair == "off"
    assert zero_on.interference.repair == "zero"
    assert dotted_keys({"interference_mitigation": False, "intf_mag_snr_db": 12.0}) == \
        {"interference.repair": "off", "interference.mag_snr_db": 12.0}


def test_a_failing_flat_key_is_named_with_its_new_key():
    with pytest.warns(DeprecationWarning), \
            pytest.raises(ValueError, match=r"intf_mitigation='median' \(now interference\."
                                            r"repair\): repair='median' is not one of"):
        P.replace(intf_mitigation="median")


@pytest.mark.parametrize("key, match", [
    ("bogus.x", r"unknown ProcessingConfig field\(s\) \['bogus.x'\]"),
    ("velocity.bogus", r"unknown VelocityConfig field\(s\) \['bogus'\]"),
    ("cfar.bogus", r"unknown CfarConfig field\(s\)")])
def test_unknown_dotted_keys_are_refused(key, match):
    with pytest.raises(ValueError, match=match):
        P.replace(**{key: 1})


def test_a_sub_config_of_the_wrong_type_is_refused():
    with pytest.raises(ValueError, match="interference must be a InterferenceConfig, got dict"):
        pipeline.ProcessingConfig(interference={"repair": "off"})


def test_interference_config_validates_the_method():
    with pytest.raises(ValueError, match=r"repair='median' is not one of \['ar'"):
        InterferenceConfig(repair="median")


def test_range_stage_cache_key_follows_every_field_of_its_sub_configs():
    """The shared range cube is keyed by the sub-config values the stage reads: a field of
    one of them (even one a hand-kept list could forget) changes the key, a setting the
    stage does not read (velocity) does not."""
    k = range_stage_key(P)
    for path, value in (("interference.hysteresis_samples", 4), ("interference.repair", "ar"),
                        ("compression.ratio", 0.4), ("range.window", "hamming"),
                        ("range.dc_removal", False)):
        assert range_stage_key(P.replace(**{path: value})) != k, path
    assert range_stage_key(P.replace(**{"velocity.tdma_disambiguation": False})) == k
    assert noise_floor_key(P.replace(**{"doppler.window": "rect"})) != noise_floor_key(P)
