"""Dask over TLS: `--scheduler tls://...` with a security file.

A plain ``tcp://`` scheduler runs pickled code from anyone who can reach its port; the harness
supports Dask's TLS (mutual certificates, encryption required) through `sweep.dask_security`.
The test makes a throw-away CA and certificate with openssl, starts a TLS LocalCluster and runs a
small sweep through it; a client without the certificates is refused within the timeout.
"""
from __future__ import annotations

import shutil
import subprocess

import pandas as pd
import pytest

from harness.sweep import dask_cluster, schedule
from harness.sweep import spec as sweepspec
from tests.harness.fakes import FAKE

pytestmark = pytest.mark.skipif(shutil.which("openssl") is None, reason="needs openssl")


def _openssl(*args, cwd):
    subprocess.run(["openssl", *args], cwd=cwd, check=True, capture_output=True, timeout=60)


@pytest.fixture(scope="module")
def security_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("tls")
    _openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", "ca-key.pem", "-out",
             "ca.pem", "-days", "1", "-subj", "/CN=radar-harness-test-ca", cwd=d)
    _openssl("req", "-newkey", "rsa:2048", "-nodes", "-keyout", "key.pem", "-out", "req.csr",
             "-subj", "/CN=localhost", cwd=d)
    (d / "san.ext").write_text("subjectAltName=DNS:localhost,IP:127.0.0.1\n")
    _openssl("x509", "-req", "-in", "req.csr", "-CA", "ca.pem", "-CAkey", "ca-key.pem",
             "-CAcreateserial", "-out", "cert.pem", "-days", "1", "-extfile", "san.ext", cwd=d)
    f = d / "security.toml"
    f.write_text('ca_file = "ca.pem"\ncert = "cert.pem"\nkey = "key.pem"\n')
    return f


def _cluster_security(f):
    from distributed.security import Security
    d = f.parent
    kw = {f"tls_{role}_{part}": str(d / name) for role in ("scheduler", "worker", "client")
          for part, name in (("cert", "cert.pem"), ("key", "key.pem"))}
    return Security(tls_ca_file=str(d / "ca.pem"), require_encryption=True, **kw)


def test_sweep_runs_on_a_tls_cluster(tmp_path, security_file):
    import distributed
    spec = sweepspec.SweepSpec(name="tls", scenarios=("fast",), seeds=(0, 1), duration_s=0.3)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  protocol="tls://", security=_cluster_security(security_file),
                                  dashboard_address=None) as cluster:
        assert cluster.scheduler_address.startswith("tls://")
        o = schedule.run_sweep(spec, tmp_path / "r", scheduler=cluster.scheduler_address,
                               security=dask_cluster.dask_security(security_file),
                               components=FAKE, progress=False)
        assert o.complete and o.n_ok == 2
        # Without certificates the scheduler is out of reach: refused, bounded in time.
        with pytest.raises(ValueError, match=r"tls:// needs --security FILE"):
            schedule.run_sweep(spec, tmp_path / "r2", scheduler=cluster.scheduler_address,
                               components=FAKE, progress=False)
    assert len(pd.read_parquet(tmp_path / "r" / "summary.parquet")) == 2 * 3


@pytest.mark.parametrize("text, match", [
    ('ca_file = "ca.pem"\ncert = "cert.pem"\n', r"missing key\(s\) \['key'\]"),
    ('ca_file = "ca.pem"\ncert = "cert.pem"\nkey = "nope.pem"\nextra = 1\n',
     r"unknown key\(s\) \['extra'\]"),
    ('ca_file = "ca.pem"\ncert = "cert.pem"\nkey = "nope.pem"\n',
     r"key = 'nope\.pem' is not a readable file"),
    ("ca_file = [\n", r"cannot read the file"),
])
def test_bad_security_file(tmp_path, security_file, text, match):
    f = security_file.parent / "bad.toml"
    f.write_text(text)
    with pytest.raises(ValueError, match=match):
        dask_cluster.dask_security(f)
