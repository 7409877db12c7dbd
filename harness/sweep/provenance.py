"""Where a results folder came from: its manifest, read safely, and the code version that
computed it compared with today's.

`gate` and `report` read results that may be days old. A gate verdict on tables of an older
code version says nothing about today's code, and the report re-simulates its maps with
today's code: both state the version of the results (`version_line`) and warn on stderr when
it is not today's (`harness.sweep.store.code_version`).
"""
from __future__ import annotations

from typing import NamedTuple

from harness.sweep import store
from harness.sweep.results_schema import read_manifest

__all__ = ["read_manifest", "ResultsVersion", "results_version", "version_line",
           "plugins_line"]


class ResultsVersion(NamedTuple):
    """Code version of a results folder and of the running code.

    results : str or None
        ``code_version`` hash recorded in the manifest (None: not recorded).
    commit : str or None
        Git commit recorded with it.
    today : str
        `harness.sweep.store.code_version` of the running code.
    """

    results: str | None
    commit: str | None
    today: str

    @property
    def current(self) -> bool:
        return self.results is not None and self.results == self.today


def results_version(manifest: dict) -> ResultsVersion:
    git = manifest.get("git") if isinstance(manifest.get("git"), dict) else {}
    v = manifest.get("code_version")
    return ResultsVersion(str(v) if v is not None else None,
                          str(git["commit"]) if git.get("commit") else None,
                          store.code_version()["hash"])


def version_line(manifest: dict) -> tuple[str, str | None]:
    """(statement of the results' code version, warning or None when it is today's)."""
    rv = results_version(manifest)
    commit = f" (git {rv.commit[:12]})" if rv.commit else ""
    if rv.results is None:
        return ("results: code version not recorded (no manifest)",
                f"warning: the results do not record their code version; today's is {rv.today}")
    line = f"results: code version {rv.results}{commit}"
    if rv.current:
        return line + ", today's", None
    return line, (f"warning: the results were computed by code version {rv.results}{commit}, "
                  f"not today's {rv.today}: rerun the sweep to judge today's code")


def plugins_line(manifest: dict) -> str | None:
    """``plugins: <module> (<distribution> <version>, source <hash>): scheme x, metric y; ...``
    of the plugins the results were made with (None: none recorded)."""
    plugins = manifest.get("plugins")
    if not isinstance(plugins, list) or not plugins:
        return None
    parts = []
    for p in plugins:
        if not isinstance(p, dict):
            continue
        where = f"{p.get('distribution')} {p.get('version')}" if p.get("distribution") \
            else str(p.get("path"))
        entries = p.get("entries") if isinstance(p.get("entries"), dict) else {}
        made = ", ".join(f"{reg} {', '.join(map(str, names))}"
                         for reg, names in sorted(entries.items()) if isinstance(names, list))
        parts.append(f"{p.get('module')} ({where}, source {p.get('sha256')})"
                     + (f": {made}" if made else ""))
    return "plugins: " + "; ".join(parts) if parts else None
