"""Reaching a Dask scheduler safely: the distributed package (an optional extra), loopback
addresses, the warning for a plain tcp:// scheduler on another host, and TLS clients
(docs/distributed.md, "Securing a cluster"). blurlab.studies.cluster sweeps through them."""

from __future__ import annotations

import os
import socket
import ssl
import warnings
from dataclasses import dataclass

INSTALL_HINT = "pip install 'blurlab[distributed]' (or dask[distributed])"


def require_distributed():
    """The dask.distributed module, or an ImportError that says how to install it."""
    try:
        import distributed
    except ImportError:
        raise ImportError(f"blurlab: sweeps on a cluster need Dask: {INSTALL_HINT}") from None
    return distributed


LOOPBACK_HOSTS = ("localhost", "127.0.0.1", "::1", "[::1]")


def is_loopback(address: str) -> bool:
    """Whether a scheduler address ('tcp://host:port', 'host:port') names this machine's
    loopback interface."""
    rest = address.split("://", 1)[-1]
    host = rest.rsplit(":", 1)[0] if rest.count(":") == 1 or rest.startswith("[") else rest
    return host in LOOPBACK_HOSTS or host.startswith("127.")


def warn_if_exposed(address: str) -> None:
    """Warns where a sweep would go to a scheduler over plain TCP on another host: Dask runs
    whatever code its clients send, so anyone who can reach that port can run code on every
    worker, and rows travel unencrypted."""
    scheme = address.split("://", 1)[0] if "://" in address else "tcp"
    if scheme == "tcp" and not is_loopback(address):
        warnings.warn(
            f"blurlab: the Dask scheduler {address} is reached over plain TCP: anyone who can "
            "reach its port can run code on every worker, and results travel unencrypted. "
            "Use a tls:// scheduler with certificates (blurlab sweep --scheduler tls://... "
            "--tls-ca --tls-cert --tls-key; docs/distributed.md, 'Securing a cluster')",
            UserWarning,
            stacklevel=3,
        )


TLS_OPTIONS = "tls_ca, tls_cert and tls_key (blurlab's --tls-ca, --tls-cert and --tls-key)"
# How long a client tries to reach a scheduler before it says so; Dask's own default is 30 s
# (a minute was seen), and a scheduler that answers at all answers within a second.
CONNECT_TIMEOUT_S = 10.0
TLS_PROBE_S = 3.0  # how long the check whether a port speaks TLS waits for the handshake


def tls_security(ca_file, cert_file, key_file):
    """A ``distributed.Security`` for a client of a TLS scheduler: the CA that signed the
    scheduler's and workers' certificates, and this client's certificate and key (PEM files).
    Encryption is required: the client refuses a plain tcp:// scheduler."""
    paths = {"CA": ca_file, "certificate": cert_file, "key": key_file}
    for what, path in paths.items():
        if path is None or not os.path.isfile(path):
            raise FileNotFoundError(
                f"blurlab: the TLS {what} file {str(path)!r} was not found; a TLS client needs "
                f"{TLS_OPTIONS}: PEM files (docs/distributed.md, 'Securing a cluster')"
            )
    return require_distributed().Security(
        tls_ca_file=str(ca_file),
        tls_client_cert=str(cert_file),
        tls_client_key=str(key_file),
        require_encryption=True,
    )


@dataclass(frozen=True)
class Scheduler:
    """A Dask scheduler to sweep on (``bl.sweep(None, ..., cluster=bl.scheduler(...))``): its
    address, the TLS files of a client of it, and how long to try to reach it. Made by
    ``scheduler()``, which checks them; ``connect()`` opens a client."""

    address: str
    tls_ca: str | None = None
    tls_cert: str | None = None
    tls_key: str | None = None
    connect_timeout_s: float = CONNECT_TIMEOUT_S

    def connect(self):
        """A ``distributed.Client`` of this scheduler. Raises ConnectionError where a plain
        tcp:// address reaches a port that speaks TLS, TimeoutError where nothing answers
        within connect_timeout_s, and PermissionError where the scheduler refuses the
        certificate's role (blurlab.studies.cluster_roles)."""
        distributed = require_distributed()
        tls = (self.tls_ca, self.tls_cert, self.tls_key)
        options = {"timeout": self.connect_timeout_s}
        if all(tls):
            options["security"] = tls_security(*tls)
        try:
            return distributed.Client(self.address, **options)
        except ImportError as error:  # the roles preload's refusal travels as the stream's error
            if "cluster roles" in str(error):
                raise PermissionError(str(error)) from None
            raise
        except (OSError, TimeoutError) as error:
            if not all(tls) and speaks_tls(self.address):
                raise ConnectionError(
                    f"blurlab: the scheduler at {self.address} speaks TLS; give its tls:// "
                    f"address and {TLS_OPTIONS} (docs/distributed.md, 'Securing a cluster')"
                ) from error
            raise TimeoutError(
                f"blurlab: no Dask scheduler answered at {self.address} within "
                f"{self.connect_timeout_s:g} s (connect_timeout_s, --connect-timeout): is it "
                f"running, on the address it printed? ({type(error).__name__}: {error})"
            ) from error


def scheduler(
    address: str,
    tls_ca=None,
    tls_cert=None,
    tls_key=None,
    connect_timeout_s: float = CONNECT_TIMEOUT_S,
) -> Scheduler:
    """The scheduler at `address` ('tls://host:8786', or 'tcp://...' on a trusted network),
    checked as ``blurlab sweep --scheduler`` checks it: a tls:// address needs all three TLS
    files (PEM: the CA, the client's certificate and its key), TLS files need a tls://
    address, and a plain tcp:// address on another host gets warn_if_exposed's warning.
    `connect_timeout_s`: how long connect() tries to reach it."""
    if not isinstance(address, str) or not address.strip():
        raise ValueError(f"blurlab: a scheduler address is a string such as "
                         f"'tls://host:8786', not {address!r}")  # fmt: skip
    if isinstance(connect_timeout_s, bool) or not (
        isinstance(connect_timeout_s, (int, float)) and 0 < connect_timeout_s <= 3600
    ):
        raise ValueError(
            "blurlab: the connect time-out (connect_timeout_s, --connect-timeout) must be "
            f"seconds in (0, 3600], not {connect_timeout_s!r}"
        )
    tls = (tls_ca, tls_cert, tls_key)
    if any(tls) and not all(tls):
        raise ValueError(f"blurlab: TLS needs all three of {TLS_OPTIONS}")
    scheme = address.split("://", 1)[0] if "://" in address else "tcp"
    if all(tls) and scheme != "tls":
        raise ValueError(
            f"blurlab: TLS certificates were given, but the scheduler address {address!r} is "
            "not tls://; give its tls:// address"
        )
    if scheme == "tls" and not all(tls):
        raise ValueError(
            f"blurlab: the scheduler {address} speaks TLS; give {TLS_OPTIONS} "
            "(docs/distributed.md, 'Securing a cluster')"
        )
    if not all(tls):
        warn_if_exposed(address)
    files = [None if path is None else str(path) for path in tls]
    return Scheduler(address, *files, connect_timeout_s=float(connect_timeout_s))


def scheduler_client(address: str, tls_ca=None, tls_cert=None, tls_key=None,
                     connect_timeout_s: float = CONNECT_TIMEOUT_S):  # fmt: skip
    """A ``distributed.Client`` of the scheduler at `address` (scheduler(...).connect())."""
    return scheduler(address, tls_ca, tls_cert, tls_key, connect_timeout_s).connect()


def speaks_tls(address: str) -> bool:
    """Whether the host:port of `address` completes a TLS handshake (its certificate
    unchecked) or answers one with a TLS alert: then it is a TLS scheduler, whatever scheme
    the address names. A plain Dask port waits for a frame and never answers one."""
    rest = address.split("://", 1)[-1]
    host, _, port = rest.rpartition(":")
    if not port.isdigit():
        return False
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.check_hostname = False
    context.verify_mode = ssl.CERT_NONE
    try:
        with socket.create_connection((host.strip("[]"), int(port)), TLS_PROBE_S) as raw:
            with context.wrap_socket(raw) as tls:
                tls.settimeout(TLS_PROBE_S)
                return tls.version() is not None
    except ssl.SSLError as error:
        return "ALERT" in str(error).upper()
    except OSError:
        return False
