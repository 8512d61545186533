"""An existing Dask cluster reached through its scheduler (``spurdyn sweep --scheduler``).

Reaching it is bounded and refused in one line naming the flag: the address is checked,
then one connection exchanges Dask's handshake within ``timeout_s`` (Dask's own connect
timeout covers opening the connection, not the scheduler's first reply: a port that
accepts and never speaks would hold ``distributed.Client`` forever), then the client
connects, a first worker must join and the workers must run this spurdyn.

Between machines the cluster can run over TLS (``tls://`` addresses): the command
presents a certificate signed by the cluster's certificate authority and checks the
scheduler's against it (:class:`TlsFiles`, Dask's ``distributed.security.Security``).
"""

from __future__ import annotations

import asyncio
import os
import threading
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator

from spurdyn.errors import InputError
from spurdyn.sweep import backends as _backends
from spurdyn.sweep.backends import DaskBackend, _close, _quiet_distributed

#: Seconds a scheduler has to answer (``--scheduler-timeout``).
CONNECT_TIMEOUT_S = 10.0

#: Seconds a scheduler has to have a first worker.
WORKERS_TIMEOUT_S = 30.0

#: The flags naming the TLS files, by field of :class:`TlsFiles`.
TLS_FLAGS = {"ca_file": "--tls-ca-file", "cert": "--tls-cert", "key": "--tls-key"}


def check_address(address: str) -> str:
    """Refuse a ``--scheduler`` that is not ``tcp://HOST:PORT`` (or ``tls://``)."""
    scheme, sep, rest = address.partition("://")
    host, colon, port = rest.rpartition(":")
    if not sep or scheme not in ("tcp", "tls") or not colon or not host or not port.isdigit():
        raise InputError("--scheduler", f"must look like tcp://HOST:PORT or tls://HOST:PORT "
                         f"(got {address!r})")
    return address


@dataclass(frozen=True)
class TlsFiles:
    """The PEM files of this end of a TLS connection to a Dask cluster.

    Attributes
    ----------
    ca_file
        The certificate authority that signed the scheduler's and workers' certificates
        (``--tls-ca-file``).
    cert
        This client's certificate, signed by the same authority (``--tls-cert``); it may
        hold the private key too.
    key
        The private key of ``cert`` when it is a file of its own (``--tls-key``).
    """

    ca_file: Path | None = None
    cert: Path | None = None
    key: Path | None = None

    def given(self) -> dict[str, Path]:
        """The files given, by field."""
        return {k: v for k, v in vars(self).items() if v is not None}


def check_tls(address: str | None, tls: TlsFiles) -> None:
    """Refuse TLS files without a ``tls://`` scheduler, a ``tls://`` scheduler without
    them (or Dask's TLS settings), and files that cannot be read."""
    given = tls.given()
    if given and (address is None or not address.startswith("tls://")):
        flag = TLS_FLAGS[next(iter(given))]
        raise InputError(flag, "is for a TLS cluster: give --scheduler tls://HOST:PORT")
    for field, path in given.items():
        if not path.is_file() or not os.access(path, os.R_OK):
            raise InputError(TLS_FLAGS[field], f"{path} is not a readable file")
    if address is None or not address.startswith("tls://"):
        return
    if tls.key is not None and tls.cert is None:
        raise InputError("--tls-key", "is the key of --tls-cert: give --tls-cert too")
    if tls.ca_file is None or tls.cert is None:
        import dask
        import distributed  # noqa: F401 - its defaults must be loaded before the config is read

        ca = dask.config.get("distributed.comm.tls.ca-file", None)
        cert = dask.config.get("distributed.comm.tls.client.cert", None)
        if not (tls.ca_file or ca) or not (tls.cert or cert):
            flag = "--tls-ca-file" if not (tls.ca_file or ca) else "--tls-cert"
            raise InputError(flag, "a tls:// scheduler needs the cluster's certificate "
                             "authority (--tls-ca-file) and a certificate it signed "
                             "(--tls-cert, --tls-key), or Dask's distributed.comm.tls settings")


def security(tls: TlsFiles) -> Any:
    """Dask's ``Security`` for ``tls``: the files given, else Dask's TLS settings;
    encryption required."""
    from distributed.security import Security

    files = {"tls_ca_file": tls.ca_file, "tls_client_cert": tls.cert,
             "tls_client_key": tls.key}
    return Security(require_encryption=True,
                    **{k: str(v) for k, v in files.items() if v is not None})


def handshake(address: str, timeout_s: float, connection_args: dict[str, Any]) -> None:
    """Open a connection to ``address`` and exchange Dask's handshake, all within
    ``timeout_s``; raise ``TimeoutError`` or ``OSError`` otherwise.

    It runs on an event loop of its own in a thread of its own, so that it works the
    same whether or not the caller runs an event loop.
    """
    from distributed.comm import connect

    async def attempt() -> None:
        comm = await asyncio.wait_for(connect(address, timeout=timeout_s, **connection_args),
                                      timeout_s)
        await comm.close()

    failure: list[BaseException] = []

    def run() -> None:
        try:
            asyncio.run(attempt())
        except BaseException as err:  # noqa: BLE001 - handed to the caller
            failure.append(err)

    thread = threading.Thread(target=run, name="spurdyn-scheduler-handshake", daemon=True)
    thread.start()
    thread.join(timeout_s + 5.0)     # the attempt is bounded; this is a second bound
    if thread.is_alive():
        raise TimeoutError(f"no answer within {timeout_s:g} s")
    if failure:
        raise failure[0]


def _refusal(address: str, err: BaseException, timeout_s: float) -> InputError:
    """The one line for a scheduler that could not be reached."""
    if isinstance(err, TimeoutError) or "Timed out" in str(err):
        why = f"within {timeout_s:g} s (--scheduler-timeout S waits longer)"
    else:
        lines = str(err).strip().splitlines()
        why = f"({type(err).__name__}: {lines[0]})" if lines else f"({type(err).__name__})"
    if address.startswith("tls://"):
        why += "; is it a TLS scheduler whose certificate --tls-ca-file signed?"
    return InputError("--scheduler", f"no Dask scheduler answered at {address} {why}")


def _connect(address: str, timeout_s: float, tls: TlsFiles) -> Any:
    """A client of the scheduler at ``address``, or the refusal (one line)."""
    from distributed import Client

    sec = security(tls) if address.startswith("tls://") else None
    try:
        args = sec.get_connection_args("client") if sec is not None else {}
    except (OSError, ValueError) as err:    # ssl.SSLError is an OSError: a bad PEM file
        flag = "--tls-cert" if tls.cert is not None else "--tls-ca-file"
        raise InputError(flag, f"cannot be used: {type(err).__name__}: {err}") from None
    try:
        handshake(address, timeout_s, args)
        return Client(address, timeout=timeout_s, set_as_default=False, security=sec)
    except (OSError, TimeoutError) as err:
        raise _refusal(address, err, timeout_s) from None


@contextmanager
def scheduler_backend(address: str, timeout_s: float = CONNECT_TIMEOUT_S,
                      workers_timeout_s: float = WORKERS_TIMEOUT_S,
                      no_worker_grace_s: float | None = None,
                      tls: TlsFiles = TlsFiles()) -> Iterator[DaskBackend]:
    """An existing Dask cluster reached through its scheduler at ``address``.

    The sweep gives up the points not yet finished once the cluster has had no worker
    for ``no_worker_grace_s`` (default :data:`~spurdyn.sweep.backends.NO_WORKER_GRACE_S`;
    they are ``not_run``; the finished ones are kept).

    Raises
    ------
    InputError
        Naming ``--scheduler``: no scheduler answers within ``timeout_s``, no worker
        joins within ``workers_timeout_s``, or the workers cannot import spurdyn; naming
        a ``--tls-*`` flag: its file cannot be used.
    """
    check_address(address)
    check_tls(address, tls)
    _quiet_distributed()
    client = _connect(address, timeout_s, tls)
    try:
        try:
            client.wait_for_workers(1, timeout=workers_timeout_s)
        except (TimeoutError, OSError):
            raise InputError("--scheduler", f"no worker joined the scheduler at {address} "
                             f"within {workers_timeout_s:g} s; start one with "
                             f"'dask worker {address}'") from None
        silence = max(timeout_s, _backends.SILENCE_S)
        try:
            versions = _within(lambda: client.run(_worker_spurdyn), silence)
        except TimeoutError:
            raise InputError("--scheduler", f"the scheduler at {address} stopped answering "
                             f"(nothing for {silence:g} s after it connected)") from None
        except Exception as err:  # noqa: BLE001 - e.g. ModuleNotFoundError on a worker
            raise InputError("--scheduler", f"the workers at {address} cannot run spurdyn "
                             f"({type(err).__name__}: {err})") from None
        from spurdyn.version import __version__

        other = sorted({v for v in versions.values() if v != __version__})
        if other:
            raise InputError("--scheduler", f"the workers run spurdyn {', '.join(other)}, "
                             f"this is {__version__}")
        n = len(versions)
        grace = _backends.NO_WORKER_GRACE_S if no_worker_grace_s is None else no_worker_grace_s
        yield DaskBackend(client, f"the Dask cluster at {address} ({n} worker"
                          f"{'s' if n != 1 else ''} now)", no_worker_grace_s=grace,
                          silence_s=silence)
    finally:
        _close(client)


def _within(call: Callable[[], Any], timeout_s: float) -> Any:
    """``call()``, waited for ``timeout_s`` at most in a thread of its own (a call to a
    frozen scheduler never returns); ``TimeoutError`` after that, its exception if it
    raised."""
    box: list[Any] = []

    def run() -> None:
        try:
            box.append((True, call()))
        except BaseException as err:  # noqa: BLE001 - handed to the caller
            box.append((False, err))

    thread = threading.Thread(target=run, name="spurdyn-scheduler-call", daemon=True)
    thread.start()
    thread.join(timeout_s)
    if not box:
        raise TimeoutError(f"no answer within {timeout_s:g} s")
    ok, value = box[0]
    if not ok:
        raise value
    return value


def _worker_spurdyn() -> str:
    from spurdyn.version import __version__

    return __version__


__all__ = ["CONNECT_TIMEOUT_S", "TlsFiles", "check_address", "check_tls", "handshake",
           "scheduler_backend", "security"]
