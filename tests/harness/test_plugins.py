"""Plugins: discovery (entry point, --plugin module, --plugin file, sweep file), the listing
with origins, a plugin that fails to import (exit 2, never half-loaded), bad plugin options,
provenance (a changed plugin changes the code version; its cells are recomputed) and a worker
that lacks a plugin.

Plugins are loaded in child processes forked from the test process (`forked.run_forked`): a
plugin loaded in the test process would stay loaded and change the code version every later
test sees, and a fork leaves the parent as it was without the few seconds of imports a fresh
CLI process costs. A command that loads no plugin (a bad option, a plugin that fails to import
and is never half loaded) runs the CLI's `main` in the test process, as the other CLI tests do.
"""
from __future__ import annotations

import importlib
import json
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import radarsim
from harness.cli import COMMANDS, main
from harness.plugins import (
    ENTRY_POINT_GROUP,
    PluginError,
    PluginInfo,
    import_builtins,
    load_plugins,
)
from harness.sweep.file import load_sweep
from harness.sweep.schedule import run_sweep
from harness.sweep.spec import SweepSpec
from harness.sweep.store import code_version
from harness.sweep.worker import execute_cell
from tests.harness.fakes import FAKE
from tests.harness.forked import run_forked

ROOT = Path(__file__).resolve().parents[2]

#: A plugin module: a TDMA scheme with its chain and a metric (names unique to these tests).
PLUGIN_SOURCE = textwrap.dedent('''
    import metrics, pipeline, radarsim
    from pipeline.mimo.tdma import TdmaChain
    from radarsim.mimo import TdmaScheme

    class Chain(TdmaChain):
        name = "{scheme}"
        variants = {{}}

    radarsim.register_scheme(TdmaScheme("{scheme}", "test plugin TDMA"))
    pipeline.register_chain(Chain())

    def _n(labelled, actor_frames):
        return float(len(labelled))

    metrics.register_metric(metrics.Metric(name="{scheme}_rows", unit="", better="none",
                            table="detections", source=_n, row_value=_n,
                            description="test plugin metric"))
''')


@pytest.fixture(scope="module", autouse=True)
def _commands_imported():
    """The command modules and every built-in registry imported once in the test process, so
    each forked CLI child finds them imported (~2-3 s CPU of imports per child otherwise)."""
    for module, _ in COMMANDS.values():
        importlib.import_module(module)
    import_builtins()


def _cli(args, *, pythonpath=None):
    """``radar-harness *args`` (the CLI's `main`) in a forked child, `pythonpath` in front of
    its ``sys.path``."""
    return run_forked(main, list(args), sys_path=[pythonpath] if pythonpath else [])


def _write_module(folder: Path, module: str, scheme: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{module}.py"
    path.write_text(PLUGIN_SOURCE.format(scheme=scheme))
    return path


def _installed(tmp_path: Path, module: str, scheme: str) -> Path:
    """A folder that, on the path, holds an installed distribution ``fake-radar-plugin 0.3``
    declaring `module` in the plugins' entry-point group."""
    site = tmp_path / "site"
    _write_module(site, module, scheme)
    info = site / "fake_radar_plugin-0.3.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fake-radar-plugin\n"
                                   "Version: 0.3\n")
    (info / "entry_points.txt").write_text(f"[{ENTRY_POINT_GROUP}]\nfake = {module}\n")
    (info / "top_level.txt").write_text(f"{module}\n")
    (info / "RECORD").write_text(f"{module}.py,,\n")
    return site


def _origin(listing: str, name: str) -> str:
    for line in listing.splitlines():
        parts = line.split(None, 2)
        if len(parts) == 3 and parts[1] == name:
            return parts[2]
    raise AssertionError(f"{name} not listed:\n{listing}")


def test_entry_point_plugin_is_loaded_by_every_command_and_listed(tmp_path):
    site = _installed(tmp_path, "fake_radar_plugin", "tdma_ep")
    r = _cli(["plugins"], pythonpath=site)
    assert r.returncode == 0, r.stderr
    assert "fake_radar_plugin" in r.stdout and "entry point" in r.stdout
    assert _origin(r.stdout, "tdma_ep") == \
        "plugin fake_radar_plugin (fake-radar-plugin 0.3)"
    assert _origin(r.stdout, "tdma_ep_rows") == \
        "plugin fake_radar_plugin (fake-radar-plugin 0.3)"
    assert _origin(r.stdout, "ddma") == "built in"
    # Another command sees the scheme too (frame checks --mimo after the plugins load).
    r = _cli(["frame", "--mimo", "tdma_ep"], pythonpath=site)
    assert r.returncode == 0, r.stderr
    assert "TDMA_EP frame" in r.stdout


def test_plugin_module_by_option(tmp_path):
    _write_module(tmp_path / "mods", "my_radar_mod", "tdma_mod")
    r = _cli(["plugins", "--plugin", "my_radar_mod", "--registry", "scheme"],
             pythonpath=tmp_path / "mods")
    assert r.returncode == 0, r.stderr
    assert _origin(r.stdout, "tdma_mod").startswith("plugin my_radar_mod (")
    assert "--plugin" in r.stdout


def test_plugin_file_by_option(tmp_path):
    path = _write_module(tmp_path, "chain_file", "tdma_file")
    r = _cli(["plugins", "--plugin", str(path), "--registry", "chain"])
    assert r.returncode == 0, r.stderr
    assert _origin(r.stdout, "tdma_file").startswith("plugin radar_harness_file_plugin_"
                                                     "chain_file_")
    assert str(path) in _origin(r.stdout, "tdma_file")


def test_a_plugin_that_fails_to_import_exits_2_naming_it(tmp_path, capsys):
    bad = tmp_path / "broken_plugin.py"
    bad.write_text("raise RuntimeError('needs libfoo.so')\n")
    assert main(["plugins", "--plugin", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.strip().count("\n") == 0, err  # one line, no traceback
    assert "plugin" in err and "broken_plugin.py" in err
    assert "RuntimeError: needs libfoo.so" in err
    assert not any(m.startswith("radar_harness_file_plugin_broken") for m in sys.modules)


def test_a_failed_plugin_is_never_half_loaded(tmp_path):
    bad = tmp_path / "half.py"
    bad.write_text("import radarsim\nfrom radarsim.mimo import TdmaScheme\n"
                   "radarsim.register_scheme(TdmaScheme('tdma_half', 'x'))\n"
                   "raise ImportError('second half missing')\n")
    with pytest.raises(PluginError, match=r"half\.py.*ImportError: second half missing"):
        load_plugins([str(bad)], entry_points=False)
    assert "tdma_half" not in radarsim.MIMO_SCHEMES
    assert not any(m.startswith("radar_harness_file_plugin_half") for m in sys.modules)


@pytest.mark.parametrize("args, message", [
    (["--registry", "nope"], r"--registry 'nope' is not one of \[.*'scheme'"),
    (["--plugin", "no/such/file.py"], r"is not a \.py file"),
    (["--plugin", "no_such_plugin_module_x"],
     r"no_such_plugin_module_x.*ModuleNotFoundError"),
    (["--plugin", ""], r"must be a list of module names"),
], ids=["unknown_registry", "missing_file", "missing_module", "empty_name"])
def test_bad_plugin_option(args, message, capsys):
    assert main(["plugins", *args]) == 2
    err = capsys.readouterr().err
    assert err.strip().count("\n") == 0, err
    assert re.search(message, err), err


def _print_schemes_and_plugins(sweep_file: Path) -> None:
    s = load_sweep(sweep_file)
    print(s.schemes, s.plugins)


def test_a_sweep_file_plugin_relative_to_the_file_adds_its_scheme(tmp_path):
    _write_module(tmp_path / "sub", "sweep_local", "tdma_sweepfile")
    f = tmp_path / "sub" / "s.toml"
    f.write_text('name = "x"\nscenarios = ["head_on_aliasing"]\nplugins = ["sweep_local.py"]\n'
                 'schemes = ["tdma", "tdma_sweepfile"]\n')
    r = run_forked(_print_schemes_and_plugins, f)
    assert r.returncode == 0, r.stderr
    assert "('tdma', 'tdma_sweepfile') ('sweep_local.py',)" in r.stdout


@pytest.mark.parametrize("value, message", [
    ('"mod"', r"plugins='mod' must be a list"),
    ("[1]", r"plugins=\[1\] must be a list"),
    ('["missing_plugin.py"]', r"missing_plugin\.py.*is not a \.py file"),
], ids=["not_a_list", "not_strings", "missing_file"])
def test_bad_sweep_file_plugins(tmp_path, value, message, capsys):
    f = tmp_path / "s.toml"
    f.write_text(f'name = "x"\nscenarios = ["head_on_aliasing"]\nplugins = {value}\n')
    assert main(["sweep", str(f), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.strip().count("\n") == 0, err
    assert re.search(message, err), err
    assert not (tmp_path / "out" / "cells").exists()  # refused before any cell ran


def _sweeps(plugin: Path, out: Path, runs: tuple[str, ...]) -> None:
    load_plugins([str(plugin)], entry_points=False)
    spec = SweepSpec(name="p", scenarios=("fast", "slow"), duration_s=0.2)
    for how in runs:
        try:
            o = run_sweep(spec, out, components=FAKE, progress=False, force=how == "force")
            print(json.dumps([o.n_ok, o.n_skipped, o.n_recomputed, code_version()["hash"]]))
        except ValueError as exc:
            print(json.dumps(str(exc)))


def _fake_sweeps(plugin: Path, out: Path, *runs: str) -> list:
    """Sweeps of the fake parts into `out`, one after the other in one forked process that
    loaded `plugin` ("force" recomputes cells of another code version, "-" does not): per
    run its [n_ok, n_skipped, n_recomputed, code version] or the refusal's message."""
    r = run_forked(_sweeps, plugin, out, runs)
    assert r.returncode == 0, r.stderr
    return [json.loads(line) for line in r.stdout.strip().splitlines()[-len(runs):]]


def test_a_changed_plugin_changes_the_code_version_and_recomputes_its_cells(tmp_path):
    plugin = _write_module(tmp_path, "versioned", "tdma_v")
    out = tmp_path / "out"
    first, again = _fake_sweeps(plugin, out, "-", "-")
    n_ok, n_skipped, _, v1 = first
    assert (n_ok, n_skipped) == (2, 0)
    assert again[:2] == [0, 2]  # unchanged: resumed
    manifest = json.loads((out / "manifest.json").read_text())
    (rec,) = manifest["plugins"]
    assert rec["path"] == str(plugin) and rec["entries"]["scheme"] == ["tdma_v"]
    plugin.write_text(plugin.read_text() + "\n# version 2\n")
    refused, forced = _fake_sweeps(plugin, out, "-", "force")
    assert "were computed by code version" in refused and "--force" in refused
    n_ok, n_skipped, n_recomputed, v2 = forced
    assert (n_ok, n_skipped, n_recomputed) == (2, 0, 2) and v2 != v1


def test_a_worker_without_the_plugin_fails_the_cell_with_one_line(tmp_path):
    from harness.cell.spec import CellSpec
    from tests.harness.fakes import FAKE
    missing = PluginInfo(name="team_dsp_plugin", how="--plugin", module="team_dsp_plugin",
                         path=None, distribution="team-dsp", version="1.2",
                         sha256="0123456789abcdef")
    r = execute_cell(CellSpec(scenario="fast", duration_s=0.2), str(tmp_path), FAKE,
                     (missing,))
    assert r["status"] == "error"
    assert "\n" not in r["error"] and "pickl" not in r["error"].lower()
    assert "this worker lacks the plugin" in r["error"]
    assert "team_dsp_plugin" in r["error"] and "install team-dsp" in r["error"]


_DASK_SCRIPT = textwrap.dedent('''
    import shutil, sys
    import distributed
    import pandas as pd
    sys.path.insert(0, sys.argv[1])
    from harness.plugins import load_plugins
    from harness.sweep.schedule import run_sweep
    from harness.sweep.spec import SweepSpec
    from tests.harness.fakes import FAKE
    spec = SweepSpec(name="d", scenarios=("fast",), duration_s=0.2)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        # A file plugin the workers cannot see: its source travels with the task.
        load_plugins([sys.argv[3]], entry_points=False)
        shutil.rmtree(sys.argv[4])
        o = run_sweep(spec, sys.argv[2] + "/file", components=FAKE,
                      scheduler=cluster.scheduler_address, progress=False)
        s = pd.read_parquet(sys.argv[2] + "/file/summary.parquet")
        print("FILE", o.n_ok, o.n_error, "tdma_file_rows" in s.columns)
        # A module plugin only the client has: the cell fails, naming it.
        load_plugins(["client_only_plugin"], entry_points=False)
        shutil.rmtree(sys.argv[1])
        o = run_sweep(spec, sys.argv[2] + "/module", components=FAKE,
                      scheduler=cluster.scheduler_address, progress=False)
    print("ERRORS", list(o.errors.values()))
''')


@pytest.mark.slow
def test_dask_workers_load_the_clients_plugins_or_fail_the_cell_naming_it(tmp_path):
    _write_module(tmp_path / "mods", "client_only_plugin", "tdma_client")
    plugin_file = _write_module(tmp_path / "files", "shipped", "tdma_file")
    r = subprocess.run([sys.executable, "-c", _DASK_SCRIPT, str(tmp_path / "mods"),
                        str(tmp_path / "out"), str(plugin_file), str(tmp_path / "files")],
                       cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "FILE 1 0 True" in r.stdout
    line = [ln for ln in r.stdout.splitlines() if ln.startswith("ERRORS")][0]
    assert "this worker lacks the plugin" in line and "client_only_plugin" in line
    assert "ModuleNotFoundError" in line and "pickl" not in line.lower()
