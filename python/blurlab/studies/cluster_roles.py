"""Separate roles on a TLS Dask cluster: a scheduler preload that lets only client certificates
send work (docs/distributed.md, "Securing a cluster").

Dask's TLS admits every certificate the cluster's CA signed, whatever it was made for, so a
worker's node.key works as a client's. Started with ``dask scheduler --preload
blurlab.studies.cluster_roles``, the scheduler reads the organizational unit (OU) of the
certificate each connection presented and answers a request only where that unit may send it:

- ``OU=client``: every request a Dask client sends (registering as a client, graphs, runs on
  the workers), but not registering as a worker;
- ``OU=node`` (the scheduler's and the workers' certificate): only what workers and nannies
  send the scheduler (registering, heartbeats, leaving).

A connection without a certificate, or whose certificate has neither unit, is refused every
request. What this cannot stop: the scheduler presents the node certificate to the workers,
which must obey it, so whoever holds node.key can command the workers directly.
"""

from __future__ import annotations

import inspect
import logging

CLIENT_UNIT = "client"
NODE_UNIT = "node"
# The requests workers and nannies send the scheduler outside their task stream
# (distributed's worker.py and nanny.py); registering as a worker is theirs alone.
NODE_ONLY = frozenset({"register-worker", "register_nanny"})
NODE_AND_CLIENT = frozenset(
    {"unregister", "heartbeat_worker", "log_event", "retire_workers", "set_resources", "who_has"}
)

logger = logging.getLogger("blurlab.cluster_roles")


def certificate_units(comm) -> set[str]:
    """The OU values in the subject of the certificate `comm`'s peer presented (none where the
    connection is not TLS)."""
    subject = (getattr(comm, "extra_info", None) or {}).get("peercert", {}).get("subject", ())
    return {value for rdn in subject for key, value in rdn if key == "organizationalUnitName"}


def allowed_units(op: str) -> frozenset[str]:
    """The certificate units that may send request `op`."""
    if op in NODE_ONLY:
        return frozenset({NODE_UNIT})
    if op in NODE_AND_CLIENT:
        return frozenset({NODE_UNIT, CLIENT_UNIT})
    return frozenset({CLIENT_UNIT})


def refusal(op: str, units: set[str]) -> str:
    """Why a request `op` from a peer whose certificate has `units` is refused."""
    wanted = " or ".join(f"OU={unit}" for unit in sorted(allowed_units(op)))
    had = ", ".join(f"OU={unit}" for unit in sorted(units)) or "no OU"
    return (
        f"blurlab cluster roles: the scheduler refuses {op!r} from a certificate with {had}; "
        f"it takes it only from one with {wanted} (docs/distributed.md, 'Securing a cluster': "
        "clients use client.pem and client.key, never the cluster's node.key)"
    )


def _guarded(op: str, handler):
    """`handler` answering only peers whose certificate unit allowed_units(op) lists."""
    takes_comm = next(iter(inspect.signature(handler).parameters), None) == "comm"
    takes_serializers = "serializers" in inspect.signature(handler).parameters

    async def guarded(comm, serializers=None, **message):
        units = certificate_units(comm)
        if not units & allowed_units(op):
            text = refusal(op, units)
            logger.warning("%s (peer %s)", text, getattr(comm, "peer_address", "?"))
            if op == "register-client":
                # The client waits for its stream's first message and raises its "error".
                await comm.write([{"op": "stream-start", "error": text}])
            raise PermissionError(text)
        if takes_serializers and serializers is not None:
            message["serializers"] = serializers
        result = handler(comm, **message) if takes_comm else handler(**message)
        return await result if inspect.isawaitable(result) else result

    guarded.__name__ = f"guarded_{getattr(handler, '__name__', op)}"
    return guarded


def dask_setup(scheduler) -> None:
    """Dask's preload hook: guards every request handler of `scheduler`."""
    for op, handler in list(scheduler.handlers.items()):
        scheduler.handlers[op] = _guarded(op, handler)
    logger.info("blurlab cluster roles: only OU=client certificates may send work")
