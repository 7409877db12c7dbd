"""The "lowrank" repair split into steps (`DeferredLowrank`), so a queue of parts on the cores
runs the frame's basis beside the flagged rows' DC removal and flags, and each chirp's repair
beside its range FFT (`pipeline.interference.rows.repaired_rows(deferred=True)`,
`pipeline.chirp_level.stage`)."""
from __future__ import annotations

import threading
from collections.abc import Callable

import numpy as np

from ..threads import inline
from .lowrank import FastTimeBasis, GramOperands, burst_row_start, gram_operands, projections
from .masks import FrameRows

__all__ = ["DeferredLowrank"]


class DeferredLowrank:
    """The "lowrank" repair of `repaired_rows(deferred=True)`: first its `steps` (the frame's
    basis; the rows' DC removal and flags; the basis' Gram sums; the rows' projections and
    the kernel's operands), each run once, then `run` on ranges of bursts (the rows of one
    chirp), each burst once. A step or `run` waits only for earlier steps: run in order, or
    taken in order by several threads (a queue), nothing waits for a step nobody took.

    Each step computes what `repaired_rows` computes eagerly (the frame's basis only: the
    frame must have its reference rows, `masks.frame_has_reference`), so the rows come out
    the same whatever thread ran what. `method` is the `methods.LowrankRepair` that made it
    (its `frame_basis` and `bursts`).
    """

    def __init__(self, y: np.ndarray, frame: FrameRows, method, hysteresis: int,
                 make_rows: Callable[[], None], make_flags: Callable[[], np.ndarray]):
        self.y, self.frame, self.method, self.hysteresis = y, frame, method, hysteresis
        self._make_rows, self._make_flags = make_rows, make_flags
        self.row_start = burst_row_start(frame.rows // frame.n_rx)  # a burst: one chirp
        self._done = [threading.Event() for _ in range(4)]
        self._basis: FastTimeBasis | None = None
        self._flags: np.ndarray | None = None
        self._operands: GramOperands | None = None
        self._fill = None

    def steps(self) -> list[Callable[[], None]]:
        """The four steps, in the order they must be taken."""
        return [self._step_basis, self._step_rows, self._step_gram, self._step_fill]

    def prepare(self) -> None:
        """Every step, here, in order (no queue)."""
        for step in self.steps():
            step()

    def run(self, b0: int, b1: int) -> None:
        """Repair bursts b0 .. b1 - 1 (after the steps; nothing if one failed: its exception
        is the caller's to raise)."""
        self._done[3].wait()
        if self._fill is not None:
            self._fill.run(b0, b1)

    def _step_basis(self) -> None:
        try:
            self._basis = self.method.frame_basis(self.frame, self.y.dtype)
        finally:
            self._done[0].set()  # also on failure: no later step waits forever

    def _step_rows(self) -> None:
        try:
            with inline():  # a step's own passes run whole: it may be on either core
                self._make_rows()
                self._flags = self._make_flags()
        finally:
            self._done[1].set()

    def _step_gram(self) -> None:
        try:
            self._done[0].wait()
            if self._basis is not None:
                self._operands = gram_operands(self._basis)
        finally:
            self._done[2].set()

    def _step_fill(self) -> None:
        try:
            self._done[0].wait()
            self._done[1].wait()
            if self._basis is None or self._flags is None:
                return
            rhs = projections(self.y, self._basis)
            self._done[2].wait()
            if self._operands is not None:
                self._fill = self.method.bursts(self.y, self._flags, self.hysteresis,
                                                self.frame, self._basis, self._operands, rhs)
        finally:
            self._done[3].set()
