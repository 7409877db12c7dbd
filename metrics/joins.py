"""Row joins of the scoring tables by integer keys: which rows of one table hold the (frame,
actor) pair of each row of another, and which row stands for each group. The pairs are coded as
integers (np.unique codes of both
sides) and matched by a stable sort and searchsorted instead of pandas merges / MultiIndexes,
whose per-call cost dominates on the few-thousand-row tables of one sweep cell.
"""
from __future__ import annotations

import copy

import numpy as np
import pandas as pd

__all__ = ["pair_index", "pair_isin", "key_join", "sorted_join", "first_valid_rows",
           "rows_by_frame", "with_columns"]


def _keys(frame: np.ndarray, actor: np.ndarray, q_frame: np.ndarray,
          q_actor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N,) and (Q,) int64 codes of the (frame, actor) pairs of the table and of the queries
    (equal pairs, equal codes)."""
    f_all, f_code = np.unique(np.concatenate([frame, q_frame]), return_inverse=True)
    a_all, a_code = np.unique(np.concatenate([actor, q_actor]), return_inverse=True)
    key = f_code.astype(np.int64) * max(len(a_all), 1) + a_code
    return key[:len(frame)], key[len(frame):]


def pair_index(frame: np.ndarray, actor: np.ndarray, q_frame: np.ndarray,
               q_actor: np.ndarray) -> np.ndarray:
    """(Q,) row of (frame, actor) holding each query pair (q_frame, q_actor), -1 if none (the
    first such row if several)."""
    ref, q = _keys(frame, actor, q_frame, q_actor)
    order = np.argsort(ref, kind="stable")
    pos = np.searchsorted(ref[order], q)
    pos = np.minimum(pos, max(len(ref) - 1, 0))
    found = (ref[order][pos] == q) if len(ref) else np.zeros(len(q), dtype=bool)
    return np.where(found, order[pos] if len(ref) else -1, -1)


def pair_isin(frame: np.ndarray, actor: np.ndarray, q_frame: np.ndarray,
              q_actor: np.ndarray) -> np.ndarray:
    """(N,) bool: the pair (frame, actor) of each row is among the query pairs."""
    return pair_index(q_frame, q_actor, frame, actor) >= 0


def key_join(q_frame: np.ndarray, q_actor: np.ndarray, frame: np.ndarray,
             actor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(P,) query and table row positions of every pair with equal (frame, actor): queries in
    order, each with its table rows in table order (an inner join's pairs)."""
    t_key, q_key = _keys(frame, actor, q_frame, q_actor)
    return sorted_join(q_key, t_key)


def sorted_join(q_key: np.ndarray, t_key: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(P,) query and table row positions of every pair with equal keys (1-D, sortable):
    queries in order, each with its table rows in table order, the row order of pandas'
    inner merge, without building the joined table."""
    order = np.argsort(t_key, kind="stable")
    sorted_key = t_key[order]
    lo = np.searchsorted(sorted_key, q_key, side="left")
    n = np.searchsorted(sorted_key, q_key, side="right") - lo
    q_i = np.repeat(np.arange(q_key.size), n)
    # Position inside each query's run of table rows: 0, 1, ... n_q - 1.
    within = np.arange(q_i.size) - np.repeat(np.cumsum(n) - n, n)
    return q_i, order[np.repeat(lo, n) + within]


def first_valid_rows(grp: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """(G,) row of each group holding its first valid value, else the group's first row.

    ``grp`` (N,) are group codes 0 .. G-1, each present (np.unique's inverse); ``valid`` (N,)
    bool. The row whose value groupby's ``first()`` returns (its first non-null), and the
    group's first row where all are null.
    """
    rows = np.unique(grp, return_index=True)[1]
    named, at = np.unique(grp[valid], return_index=True)
    rows[named] = np.flatnonzero(valid)[at]
    return rows


def rows_by_frame(frame: np.ndarray) -> dict:
    """Frame -> (m,) rows of `frame` holding it, ascending (one stable sort, not one scan of
    every row per frame)."""
    order = np.argsort(frame, kind="stable")
    keys, starts = np.unique(frame[order], return_index=True)
    return dict(zip(keys.tolist(), np.split(order, starts[1:])))


def with_columns(df: pd.DataFrame, columns: dict) -> pd.DataFrame:
    """A copy of `df` with `columns` (name -> (N,) array) appended in order: what assigning
    them one by one to ``df.copy()`` gives, dtypes included, in one concatenation (each
    assignment re-builds the table's column index: ~0.15-0.25 ms apiece under pandas 3). A
    name `df` already has is assigned in place, as an assignment would."""
    if not columns:
        return df.copy()
    if any(c in df.columns for c in columns):
        out = df.copy()
        for c, v in columns.items():
            out[c] = v
        return out
    out = pd.concat([df, pd.DataFrame(columns, index=df.index)], axis=1)
    out.attrs = copy.deepcopy(df.attrs)  # as df.copy() keeps them
    return out
