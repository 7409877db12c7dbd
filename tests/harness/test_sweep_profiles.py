"""Sweeps with TI profiles per variant and association settings from each cell's config."""
from __future__ import annotations

import textwrap

import pandas as pd
import pytest

import radarsim
from harness.cell.config import build_configs, cell_association, radar_config
from harness.cell.run import run_cell
from harness.cell.spec import CellSpec
from harness.sweep.file import load_sweep
from harness.sweep.schedule import run_sweep
from metrics import detection as mdet
from radarsim.ti import to_ti_cfg
from tests.harness.fakes import FAKE


@pytest.fixture
def x18_profile(tmp_path):
    """An xWR18xx TDMA complex profile (3 Tx, 384 chirps: 128 Doppler bins as TDMA, 96 as
    DDMA, room for the default CFAR window), written next to the sweep file."""
    cfg = radarsim.RadarConfig.from_fields(
        chip="AWR1843", adc_mode="complex1x", mimo="tdma", n_tx=3, n_chirps=384, n_samples=64,
        adc_rate_sps=10e6)
    (tmp_path / "profiles").mkdir()
    path = tmp_path / "profiles" / "x18.cfg"
    path.write_text(to_ti_cfg(cfg, frame_period_s=0.1))
    return path, cfg


def _sweep_file(tmp_path, body: str):
    f = tmp_path / "s.toml"
    f.write_text(textwrap.dedent(body))
    return f


def test_radar_profile_key_resolves_relative_to_the_sweep_file(tmp_path, x18_profile):
    path, cfg = x18_profile
    f = _sweep_file(tmp_path, """
        name = "p"
        scenarios = ["fast"]
        [vary]
        "radar.profile" = ["profiles/x18.cfg"]
    """)
    spec = load_sweep(f, check_scenarios=False)
    (v,) = spec.variants
    assert v.radar["profile"] == str(path.resolve())
    cell = spec.cells()[0]
    radar, _ = build_configs(cell, FAKE)
    assert radar["tdma"] == cfg
    # The DDMA scheme runs the profile's waveform with DDMA (3 Tx: 4 sub-bands).
    assert radar["ddma"] == cfg.replace(mimo="ddma")


def test_profile_compared_with_the_r79_preset_in_one_sweep(tmp_path, x18_profile):
    f = _sweep_file(tmp_path, """
        name = "cmp"
        scenarios = ["fast"]
        duration_s = 0.3
        schemes = ["tdma"]
        baseline_scheme = "tdma"
        [[variants]]
        name = "r79"
        [[variants]]
        name = "mine"
        radar = {profile = "profiles/x18.cfg"}
    """)
    spec = load_sweep(f, check_scenarios=False)
    out = run_sweep(spec, tmp_path / "out", components=FAKE, progress=False)
    assert out.n_error == 0, out.errors
    summary = pd.read_parquet(out.out_dir / "summary.parquet")
    assert set(summary["variant"]) == {"r79", "mine"}


def test_bad_profile_in_a_sweep_is_named(tmp_path):
    (tmp_path / "bad.cfg").write_text("sensorStop\nprofileCfg 0 77\n")
    f = _sweep_file(tmp_path, """
        name = "p"
        scenarios = ["fast"]
        [vary]
        "radar.profile" = ["bad.cfg", "missing.cfg"]
    """)
    with pytest.raises(ValueError, match=r"radar.profile='.*bad.cfg': line 2"):
        load_sweep(f, check_scenarios=False)


def test_profile_that_cannot_run_a_scheme_names_it(tmp_path):
    cfg = radarsim.RadarConfig.from_fields(
        chip="AWR1642", adc_mode="complex1x", mimo="tdma", n_tx=2, n_chirps=32, n_samples=64,
        adc_rate_sps=5e6)
    path = tmp_path / "x16.cfg"
    path.write_text(to_ti_cfg(cfg))
    assert radar_config({"profile": str(path)}, "tdma") == cfg
    with pytest.raises(ValueError, match=r"radar.profile=.*x16.cfg' \(AWR1642, tdma\) as scheme "
                                         r"'ddma': .*no"):
        radar_config({"profile": str(path)}, "ddma")


def test_association_follows_each_cells_config(x18_profile):
    """Window = widest unambiguous velocity of the cell's schemes, FOV = the board's, max
    range = the config's; never the R79 numbers unless the cell is the R79 preset."""
    _, cfg = x18_profile
    radar = {"ddma": cfg.replace(mimo="ddma"), "tdma": cfg}
    a = cell_association(radar)
    assert a.unambiguity_window_mps == pytest.approx(cfg.wavelength_m / (4 * cfg.chirp_period_s))
    assert a.fov_deg == 60.0                      # AWR1843BOOST
    assert a.max_range_m == pytest.approx(cfg.max_range_m)
    r79 = {m: radarsim.presets.r79(m) for m in ("ddma", "tdma")}
    b = cell_association(r79)
    assert b.fov_deg == 80.0 and b.max_range_m == pytest.approx(253.12, abs=0.01)
    assert b.unambiguity_window_mps == pytest.approx(40.88, abs=0.01)
    # An explicit [association] wins.
    assert cell_association(r79, {"fov_deg": 45.0}).fov_deg == 45.0


def test_association_section_reaches_the_cells(tmp_path):
    f = _sweep_file(tmp_path, """
        name = "a"
        scenarios = ["fast"]
        [association]
        fov_deg = 30.0
    """)
    spec = load_sweep(f, check_scenarios=False)
    assert spec.cells()[0].association == {"fov_deg": 30.0}
    bad = _sweep_file(tmp_path, """
        name = "a"
        scenarios = ["fast"]
        [association]
        fov = 30.0
    """)
    with pytest.raises(ValueError, match=r"\[association\]: .*fov"):
        load_sweep(bad, check_scenarios=False)
    # Cells without overrides keep their ids (and so resume old results).
    assert "association" not in CellSpec(scenario="x").cell_id


def test_run_cell_uses_the_cell_association(monkeypatch):

    seen = {}
    real = mdet.summarize_scheme

    def spy(lab, af, n, assoc, **kw):
        seen["assoc"] = assoc
        return real(lab, af, n, assoc, **kw)

    monkeypatch.setattr(mdet, "summarize_scheme", spy)
    run_cell(CellSpec(scenario="fast", duration_s=0.2, association={"max_range_m": 99.0}), FAKE)
    assert seen["assoc"].max_range_m == 99.0 and seen["assoc"].fov_deg == 80.0


def test_sweep_cell_and_process_read_a_profile_into_the_same_configs(tmp_path):
    """One function (harness.cell.ti_profile) for both: the cell's TDMA radar and processing are
    exactly what `radar-harness process` runs for the profile (its cfarCfg as the CFAR, no
    compression / mitigation / extension, its fields of view); the sweep's [processing] still
    overrides."""
    from harness.cell.components import default_components
    from harness.cell.ti_profile import load_profile, processing_from_profile
    from tests.radarsim.profiles import PROFILE_DIR

    path = PROFILE_DIR / "xwr68_tx13.cfg"
    f = _sweep_file(tmp_path, f"""
        name = "p"
        scenarios = ["fast"]
        schemes = ["tdma"]
        [[variants]]
        name = "mine"
        radar = {{profile = "{path}"}}
    """)
    cell = load_sweep(f, check_scenarios=False).cells()[0]
    radar, procs = build_configs(cell, default_components())
    prof = load_profile(path)
    assert radar["tdma"] == prof.radar
    assert procs["tdma"] == processing_from_profile(prof)
    assert procs["tdma"].cfar.threshold_db == 15.0 and not procs["tdma"].compression.enabled
    assert not procs["tdma"].velocity.tdma_disambiguation
    f2 = _sweep_file(tmp_path, f.read_text() + "processing = {tdma_disambiguation = true}\n")
    cell = load_sweep(f2, check_scenarios=False).cells()[0]
    _, procs = build_configs(cell, default_components())
    assert procs["tdma"] == processing_from_profile(prof).replace(tdma_disambiguation=True)


def test_advanced_frame_profile_is_refused_by_a_sweep_before_it_starts(tmp_path):
    from tests.radarsim.profiles import PROFILE_DIR

    path = PROFILE_DIR / "xwr68_advanced_subframes.cfg"
    f = _sweep_file(tmp_path, f"""
        name = "p"
        scenarios = ["fast"]
        schemes = ["tdma"]
        [[variants]]
        name = "adv"
        radar = {{profile = "{path}"}}
    """)
    with pytest.raises(ValueError, match=r"an advanced-frame profile has one radar per "
                                         r"sub-frame \(2\), a sweep cell runs one"):
        spec = load_sweep(f, check_scenarios=False)
        build_configs(spec.cells()[0], FAKE)


def test_profile_clutter_removal_with_a_ddma_scheme_is_refused_before_the_sweep(tmp_path):
    """clutterRemoval 1 belongs to the TDM demos; the DDMA chain has none: the sweep names it
    at validation, not at the first frame."""
    path = tmp_path / "x18.cfg"
    cfg = radarsim.RadarConfig.from_fields(
        chip="AWR1843", adc_mode="complex1x", mimo="tdma", n_tx=3, n_chirps=384, n_samples=64,
        adc_rate_sps=10e6)
    path.write_text(to_ti_cfg(cfg, frame_period_s=0.1, extra_lines=["clutterRemoval -1 1"]))
    f = _sweep_file(tmp_path, f"""
        name = "p"
        scenarios = ["fast"]
        schemes = ["tdma", "ddma"]
        [[variants]]
        name = "mine"
        radar = {{profile = "{path}"}}
    """)
    with pytest.raises(ValueError, match=r"clutter_removal=True .*: the ddma chain has no "
                                         r"static clutter removal"):
        load_sweep(f, check_scenarios=False)


@pytest.mark.parametrize("enabled", [True, False])
def test_sweep_names_what_its_profile_asks_and_cells_do_not_run(tmp_path, capsys, enabled):
    """A sweep prints, once per profile, the notes `process` prints (here the xwr68_tx13
    profile's CQRxSatMonitor, read but not modelled) and the capture-level calibDcRangeSig a
    cell does not run: nothing a profile asks for is dropped silently."""
    from harness.cli.cmd_sweep import _print_profile_notes
    from tests.radarsim.profiles import profile_text
    off = "calibDcRangeSig -1 0 -5 8 256"
    text = profile_text("xwr68_tx13")
    (tmp_path / "p.cfg").write_text(text.replace(off, "calibDcRangeSig -1 1 -5 8 32")
                                    if enabled else text)
    f = _sweep_file(tmp_path, """
        name = "p"
        scenarios = ["fast"]
        schemes = ["tdma"]
        baseline_scheme = "tdma"
        [vary]
        "radar.profile" = ["p.cfg"]
    """)
    _print_profile_notes(load_sweep(f, check_scenarios=False))
    err = capsys.readouterr().err.splitlines()
    assert all(line.startswith(f"note: radar.profile={tmp_path / 'p.cfg'}: ") for line in err)
    assert sum("read but not modelled: " in line and "CQRxSatMonitor" in line
               for line in err) == 1
    assert any("calibDcRangeSig not applied in a sweep cell" in line for line in err) == enabled
