"""Reaching a Dask scheduler safely: the distributed package (an optional extra), loopback
addresses, the warning for a plain tcp:// scheduler on another host, and TLS clients
(docs/distributed.md, "Securing a cluster"). blurlab.studies.cluster sweeps through them."""

from __future__ import annotations

import os
import warnings

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


def tls_security(ca_file, cert_file, key_file):
    """A ``distributed.Security`` for a client of a TLS scheduler: the CA that signed the
    scheduler's and workers' certificates, and this client's certificate and key (PEM files).
    Encryption is required: the client refuses a plain tcp:// scheduler."""
    paths = {"CA": ca_file, "certificate": cert_file, "key": key_file}
    for what, path in paths.items():
        if path is None or not os.path.isfile(path):
            raise FileNotFoundError(
                f"blurlab: the TLS {what} file {path!r} was not found; a TLS client needs "
                "--tls-ca, --tls-cert and --tls-key (PEM files, docs/distributed.md)"
            )
    return require_distributed().Security(
        tls_ca_file=str(ca_file),
        tls_client_cert=str(cert_file),
        tls_client_key=str(key_file),
        require_encryption=True,
    )


def scheduler_client(address: str, tls_ca=None, tls_cert=None, tls_key=None):
    """A ``distributed.Client`` of the scheduler at `address`: with TLS files, a tls://
    address and its Security (tls_security); without, a plain one (warn_if_exposed)."""
    tls = (tls_ca, tls_cert, tls_key)
    if any(tls) and not all(tls):
        raise ValueError("blurlab: TLS needs all three of --tls-ca, --tls-cert and --tls-key")
    scheme = address.split("://", 1)[0] if "://" in address else "tcp"
    if all(tls) and scheme != "tls":
        raise ValueError(
            f"blurlab: TLS certificates were given, but the scheduler address {address!r} is "
            "not tls://; give its tls:// address"
        )
    if scheme == "tls" and not all(tls):
        raise ValueError(
            f"blurlab: the scheduler {address} speaks TLS; give --tls-ca, --tls-cert and "
            "--tls-key (docs/distributed.md, 'Securing a cluster')"
        )
    if not all(tls):
        warn_if_exposed(address)
        return require_distributed().Client(address, timeout="60s")
    return require_distributed().Client(address, security=tls_security(*tls), timeout="60s")
