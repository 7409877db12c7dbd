"""metrics.joins: integer-key joins and group rows against their pandas formulations."""
import numpy as np
import pandas as pd

from metrics.joins import first_valid_rows, with_columns


def test_first_valid_rows_is_groupby_first_else_the_first_row():
    """The row of each group's first non-null value (groupby's first()), the group's first row
    where all its values are null; shuffled groups, groups of one row."""
    g = np.random.default_rng(2)
    key = g.integers(0, 12, 200)
    cls = pd.Series(g.choice(np.array(["car", "truck", None], dtype=object), 200,
                             p=[0.2, 0.1, 0.7]))
    cls[key == 5] = None  # one group with no class at all
    ids, grp = np.unique(key, return_inverse=True)
    rows = first_valid_rows(grp, cls.notna().to_numpy())
    want = cls.groupby(key).first()
    got = cls.to_numpy()[rows]
    assert np.array_equal(grp[rows], np.arange(ids.size))
    assert pd.isna(got[ids == 5][0]) and rows[ids == 5][0] == np.flatnonzero(key == 5)[0]
    named = ids != 5
    assert list(got[named]) == list(want.loc[ids[named]])


def test_with_columns_is_assigning_them_one_by_one():
    df = pd.DataFrame({"a": [1.0, 2.0, 3.0], "s": ["x", "y", "z"]}, index=[5, 3, 9])
    df.attrs["saturation"] = {"n": 1}
    cols = {"label": np.array(["TRUE", "", "GHOST"], dtype=object),
            "k": np.arange(3, dtype=np.int64), "a": np.zeros(3)}
    for new in (dict(list(cols.items())[:2]), cols):   # new names only; one already there
        ref = df.copy()
        for c, v in new.items():
            ref[c] = v
        got = with_columns(df, new)
        pd.testing.assert_frame_equal(got, ref, check_exact=True)
        assert got.attrs == ref.attrs and got is not df
    assert list(df.columns) == ["a", "s"]
