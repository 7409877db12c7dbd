"""Placeholder: filled in by the issue that builds this command."""
from __future__ import annotations


def add_arguments(parser) -> None:
    pass


def run(args) -> int:
    raise NotImplementedError("command not built yet")
