"""core.config: dotted keys into nested frozen configs, flat keys translated with a warning."""
from __future__ import annotations

import dataclasses

import pytest

from core.config import (
    dotted_changes,
    flat_given,
    flat_key,
    replace_path,
    replace_paths,
    split_paths,
)
from core.errors import BadInput


@dataclasses.dataclass(frozen=True)
class Inner:
    pfa: float = 1e-6
    window: int = 16

    def __post_init__(self):
        if not 0 < self.pfa < 1:
            raise BadInput(f"pfa={self.pfa!r} must be in (0, 1)")


@dataclasses.dataclass(frozen=True)
class Outer:
    inner: Inner = Inner()
    name: str = "x"


GROUPS = {"inner": Inner}
FLAT = {"pfa": "inner.pfa"}


def test_replace_path_sets_one_nested_field_and_keeps_the_rest():
    out = replace_path(Outer(), "inner.pfa", 1e-5)
    assert out == Outer(inner=Inner(pfa=1e-5, window=16))


def test_replace_paths_sets_a_top_field_and_nested_fields_together():
    out = replace_paths(Outer(), {"name": "y", "inner.window": 8})
    assert (out.name, out.inner.window, out.inner.pfa) == ("y", 8, 1e-6)


def test_a_nested_change_is_validated_by_its_sub_config():
    with pytest.raises(BadInput, match=r"pfa=2 must be in \(0, 1\)"):
        replace_path(Outer(), "inner.pfa", 2)


def test_an_unknown_head_is_refused_with_the_known_fields():
    with pytest.raises(BadInput, match=r"unknown Outer field 'outer'; known: \['inner', 'name'\]"):
        replace_path(Outer(), "outer.pfa", 1e-5)


def test_split_paths():
    assert split_paths({"a": 1, "b.c": 2, "b.d.e": 3}) == ({"a": 1}, {"b": {"c": 2, "d.e": 3}})


def test_dotted_changes_translates_a_flat_key_and_warns_with_the_new_key():
    with pytest.warns(DeprecationWarning, match=r"Outer key 'pfa' is deprecated: use 'inner.pfa'"):
        assert dotted_changes({"pfa": 1e-5}, GROUPS, FLAT, "Outer") == {"inner.pfa": 1e-5}


def test_dotted_changes_without_warning_for_a_bridge(recwarn):
    assert dotted_changes({"pfa": 1e-5}, GROUPS, FLAT, "Outer", warn=False) == {"inner.pfa": 1e-5}
    assert not [w for w in recwarn if issubclass(w.category, DeprecationWarning)]


def test_dotted_changes_expands_a_table_of_a_sub_config_and_keeps_a_whole_one():
    assert dotted_changes({"inner": {"pfa": 1e-5, "window": 8}}, GROUPS, FLAT, "Outer") == \
        {"inner.pfa": 1e-5, "inner.window": 8}
    whole = Inner(window=4)
    assert dotted_changes({"inner": whole}, GROUPS, FLAT, "Outer") == {"inner": whole}


def test_dotted_changes_refuses_an_unknown_key():
    with pytest.raises(BadInput, match=r"unknown Outer field\(s\) \['bogus'\]"):
        dotted_changes({"bogus": 1}, GROUPS, FLAT, "Outer")


def test_flat_key_by_table_then_by_prefix():
    assert flat_key("pfa", FLAT, {"inner_": "inner."}) == "inner.pfa"
    assert flat_key("inner_window", FLAT, {"inner_": "inner."}) == "inner.window"
    assert flat_key("inner_window", FLAT) is None


def test_dotted_changes_names_the_sweep_file_key_in_the_warning():
    with pytest.warns(DeprecationWarning, match=r"use 'inner.window' \(sweep files: "
                                                r"'things.inner.window'\)"):
        dotted_changes({"inner_window": 8}, GROUPS, FLAT, "Outer", prefixes={"inner_": "inner."},
                       section="things")


@pytest.mark.parametrize("changes, match", [
    ({"inner.bogus": 1}, r"unknown Inner field\(s\) \['bogus'\] \('inner.bogus'\)"),
    ({"inner": {"bogus": 1}}, r"unknown Inner field\(s\) \['bogus'\]"),
    ({"inner_bogus": 1}, r"unknown Inner field\(s\) \['inner_bogus'\] \('inner.bogus'\)")])
def test_dotted_changes_checks_the_fields_of_a_sub_config_when_asked(changes, match, recwarn):
    assert dotted_changes(changes, GROUPS, FLAT, "Outer", prefixes={"inner_": "inner."},
                          warn=False) != {}
    with pytest.raises(BadInput, match=match):
        dotted_changes(changes, GROUPS, FLAT, "Outer", prefixes={"inner_": "inner."},
                       check_fields=True, warn=False)


def test_a_flat_key_that_names_a_sub_config_too_takes_its_table():
    flat = {"inner": "inner.pfa"}
    assert dotted_changes({"inner": 1e-5}, GROUPS, flat, "Outer", warn=False) == \
        {"inner.pfa": 1e-5}
    assert dotted_changes({"inner": {"window": 8}}, GROUPS, flat, "Outer") == {"inner.window": 8}


def test_replace_paths_uses_a_sub_config_s_own_replace():
    def doubled(inner, changes):
        return dataclasses.replace(inner, **{k: 2 * v for k, v in changes.items()})
    assert replace_paths(Outer(), {"inner.window": 8}, {"inner": doubled}).inner.window == 16


def test_a_refused_change_names_the_flat_key_it_was_given_by():
    given = flat_given({"pfa": 2, "name": "y"}, FLAT)
    assert given == {"pfa=2 (now inner.pfa)": "inner.pfa"}
    with pytest.raises(BadInput, match=r"^pfa=2 \(now inner.pfa\): pfa=2 must be in"):
        replace_paths(Outer(), {"inner.pfa": 2, "name": "y"}, given=given)
