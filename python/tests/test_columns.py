"""run_trace's and plan_many's arrays are the library's column table (hp_trace_columns.h),
as `headplan batch --columns` lists it and headplan.columns() returns it: the keys, dtypes
and shapes, in the table's order."""
import numpy as np

import headplan

from conftest import DEFAULT, cli

DTYPE_KIND = {"number": "f", "integer": "i", "flags": "u", "text": "U"}


def table():
    rc, out, err = cli("batch", "--columns")
    assert rc == 0, err
    lines = out.splitlines()
    head = lines[0].split("\t")
    return [dict(zip(head, l.split("\t"))) for l in lines[1:]]


def test_module_table_is_the_programs():
    listed = table()
    mine = headplan.columns()
    assert len(mine) == len(listed)
    for c, l in zip(mine, listed):
        assert (c["name"], c["unit"], c["format"], c["shape"]) == \
            (l["name"], l["unit"], l["format"], l["shape"])
        assert c["rows"] == (l["rows"] == "yes") and c["measured"] == (l["measured"] == "yes")
        assert (c["numpy"] or "-") == l["numpy"]
        assert (c["dtype"] is None) == (c["numpy"] is None)


def check(r, cols, N, n):
    want = [c["numpy"] for c in cols]
    assert [k for k in r if k != "messages"] == want
    dtypes = {c["numpy"]: c["dtype"] for c in headplan.columns() if c["numpy"]}
    for c in cols:
        a = r[c["numpy"]]
        shape = {"one": (N,), "axes": (N, 6), "bladders": (N, n)}[c["shape"]]
        assert a.shape == shape, (c["numpy"], a.shape, shape)
        assert a.dtype.kind == DTYPE_KIND[c["format"]], (c["numpy"], a.dtype)
        assert a.dtype.kind == "U" if dtypes[c["numpy"]] == "str" else \
            a.dtype == np.dtype(dtypes[c["numpy"]]), (c["numpy"], a.dtype)


def test_run_trace_keys_are_the_tables(tmp_path):
    trace = tmp_path / "t.csv"
    trace.write_text("# headplan-trace: rows=correction\n"
                     "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n"
                     "0,0.5,0,0,0,0,0\n0.1,nan,0,0,0,0,0\n0.2,0.2,0.1,0,0.1,0,0\n")
    p = headplan.Planner(headplan.load_scene(DEFAULT))
    r = p.run_trace(str(trace))
    cols = [c for c in table() if c["numpy"] != "-"]
    assert "messages" in r
    check(r, cols, 3, len(p.bladder_names))
    # The bad row: status bad-row (code -1), NaN numbers, no binding flags.
    assert r["status"][1] == "bad-row" and r["status_code"][1] == -1
    assert np.all(np.isnan(r["pressure_pa"][1])) and not r["binding"][1].any()
    # plan_many: the same without the trace-row columns (line, t_s).
    m = p.plan_many(np.zeros((2, 6)))
    check(m, [c for c in cols if c["name"] not in ("line", "t_s")], 2, len(p.bladder_names))
