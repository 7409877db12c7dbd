"""Running sweep cells on a Dask distributed cluster (TLS with `dask_security`).

Workers must see the output directory, which the scheduler makes absolute first
(`harness.sweep.schedule.prepare_out`).
"""
from __future__ import annotations

from pathlib import Path

from core.checks import read_toml
from core.errors import BadInput
from core.fileio import check_input_file
from harness.sweep.worker import execute_cell

__all__ = ["dask_security", "run_dask", "DEFAULT_SCHEDULER_TIMEOUT_S"]


#: Default wait for a Dask scheduler to answer, s.
DEFAULT_SCHEDULER_TIMEOUT_S = 20.0


def dask_security(path: str | Path | None):
    """`distributed.Security` for TLS from a TOML file (None: Dask's own configuration,
    ``distributed.comm.tls.*``).

    The file holds ``ca_file``, ``cert`` and ``key`` (PEM paths, relative to the file)::

        ca_file = "ca.pem"      # the CA that signed the scheduler's and workers' certificates
        cert = "client.pem"     # this client's certificate
        key = "client-key.pem"  # and its private key

    Raises
    ------
    ValueError
        Unreadable file, unknown or missing keys, a PEM file that does not exist.
    """
    from distributed.security import Security
    if path is None:
        return Security()
    p = Path(path)
    try:
        data = read_toml(p, "--security")
    except (OSError, ValueError) as exc:
        raise BadInput(f"--security {str(path)!r}: cannot read the file ({exc})") from None
    keys = {"ca_file", "cert", "key"}
    bad, miss = sorted(set(data) - keys), sorted(keys - set(data))
    if bad or miss:
        raise BadInput(f"--security {str(path)!r}: unknown key(s) {bad}, missing key(s) "
                       f"{miss}; needs {sorted(keys)}")
    files = {}
    for k in sorted(keys):
        v = data[k]
        f = (p.parent / v) if isinstance(v, str) else None
        if f is None or not f.is_file():
            raise BadInput(f"--security {str(path)!r}: {k} = {v!r} is not a readable file")
        check_input_file(f, f"--security {str(path)!r}: {k}")
        files[k] = str(f.resolve())
    _check_pem(str(path), files)
    return Security(tls_ca_file=files["ca_file"], tls_client_cert=files["cert"],
                    tls_client_key=files["key"], require_encryption=True)


def _check_pem(path: str, files: dict[str, str]) -> None:
    """Load the CA, certificate and key as the TLS client will, so a garbage or mismatched PEM
    is reported as such (not later as "no Dask scheduler answered")."""
    import ssl
    try:
        ctx = ssl.create_default_context(cafile=files["ca_file"])
    except (ssl.SSLError, OSError) as exc:
        raise BadInput(f"--security {path!r}: ca_file = {Path(files['ca_file']).name!r} is "
                       f"not a PEM CA certificate ({getattr(exc, 'reason', None) or exc})"
                       ) from None
    try:
        ctx.load_cert_chain(files["cert"], files["key"])
    except (ssl.SSLError, OSError) as exc:
        raise BadInput(f"--security {path!r}: cert = {Path(files['cert']).name!r} and key = "
                       f"{Path(files['key']).name!r} are not a PEM certificate and its "
                       f"private key ({getattr(exc, 'reason', None) or exc})") from None


def _connect(scheduler, security, timeout_s: float):
    from distributed import Client
    if isinstance(scheduler, Client):
        return scheduler
    addr = str(scheduler)
    if "://" not in addr:
        raise BadInput(f"--scheduler {addr!r}: give a protocol, tls://host:port (or tcp:// "
                       "on a trusted network)")
    proto = addr.split("://", 1)[0]
    if proto not in ("tls", "tcp", "inproc", "ws", "wss", "ucx"):
        raise BadInput(f"--scheduler {addr!r}: unknown protocol {proto!r}")
    if proto == "tls":
        security = security if security is not None else dask_security(None)
        if not getattr(security, "tls_ca_file", None):
            raise BadInput(f"--scheduler {addr!r}: tls:// needs --security FILE (ca_file, "
                           "cert, key) or Dask's distributed.comm.tls configuration")
    try:
        return Client(addr, timeout=f"{timeout_s}s", security=security)
    except (OSError, TimeoutError) as exc:
        raise BadInput(f"--scheduler {addr!r}: no Dask scheduler answered within "
                       f"{timeout_s:g} s ({type(exc).__name__}: {exc})") from None


def run_dask(pending, out, scheduler, components, bar, security=None,
             timeout_s: float = DEFAULT_SCHEDULER_TIMEOUT_S, plugins=()):
    """Run cells on a Dask cluster; returns (results by cell id, ids whose task failed).

    Every task carries the client's plugins (`harness.plugins.PluginInfo`, a file plugin with
    its source): the worker loads them before the cell (`execute_cell`)."""
    from distributed import as_completed
    client = _connect(scheduler, security, timeout_s)
    try:
        try:  # a scheduler without workers would leave every task waiting forever
            client.wait_for_workers(1, timeout=timeout_s)
        except (TimeoutError, OSError):
            raise BadInput(f"--scheduler {client.scheduler.address!r}: no Dask worker joined "
                           f"the scheduler within {timeout_s:g} s") from None
        futs = {client.submit(execute_cell, c, str(out), components, plugins,
                              key=f"cell-{c.cell_id}", pure=False): c for c in pending}
        res, lost = {}, []
        for fut in as_completed(list(futs)):
            try:
                r = fut.result()
                res[r["cell_id"]] = r
            except Exception:  # noqa: BLE001 - a killed worker (KilledWorker) loses the task
                lost.append(futs[fut].cell_id)
            bar.update(1)
        return res, lost
    finally:
        if client is not scheduler:
            client.close()
