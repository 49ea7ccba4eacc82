"""A TLS Dask cluster started with the very commands of docs/distributed.md, "Securing a
cluster" (read from the page; another free port for 8786): certificates made with openssl, a
`dask scheduler` with blurlab's roles preload and a `dask worker` process (two workers), on
the loopback interface. Every port they open listens on loopback (`ss`, as the page shows). A
sweep through `blurlab sweep --scheduler tls://...` gives a local sweep's rows, bit for bit but
for the pass times; a client presenting the workers' node certificate, one whose certificate
another CA signed, one without TLS, and `blurlab sweep` without the certificates are refused."""

from __future__ import annotations

import json
import os
import re
import shlex
import socket
import subprocess
import sys
import time
import warnings
from pathlib import Path

import pandas as pd
import pytest
from conftest import CLI_DEVICE
from method_picks import pick
from process_group import START_TIMEOUT_S, stop_group, wait_for_file

import blurlab as bl
from blurlab.studies import scheduler

pytest.importorskip("distributed")

SCENES = ["fan", "crossing"]
SIZE = (32, 18)
SWEEP_TIMEOUT_S = 300
GATHER = pick(kind="gather", params=("taps",))  # a gather with taps
REFUSED_TIMEOUT_S = 10
TOML = (
    f"scenes = {json.dumps(SCENES)}\nsize = {json.dumps(list(SIZE))}\nreference_samples = 8\n"
    'metrics = ["psnr", "ssim"]\nout = "{out}"\n'
    f"[methods.{GATHER}]\ntaps = [2, 4]\n"
)
PAGE = Path(__file__).resolve().parents[1] / "docs" / "distributed.md"
DOCUMENTED_PORT = "8786"


def documented_commands() -> list[str]:
    """The lines of the code blocks of the page's "Securing a cluster" section, in order."""
    section = PAGE.read_text().split("## Securing a cluster (TLS)", 1)[1].split("\n### ", 1)[0]
    blocks = re.findall(r"^\s*```\n(.*?)^\s*```", section, re.S | re.M)
    return [line.strip() for block in blocks for line in block.splitlines() if line.strip()]


def documented(prefix: str, port: int) -> list[str]:
    """The page's commands that start with `prefix`, on `port` instead of 8786."""
    lines = [c for c in documented_commands() if c.startswith(prefix)]
    assert lines, f"docs/distributed.md, 'Securing a cluster', has no {prefix!r} command"
    return [line.replace(DOCUMENTED_PORT, str(port)) for line in lines]


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start_documented(command: str, folder: Path, log: Path, env: dict) -> subprocess.Popen:
    """A page's `dask ...` command through this Python (python -m dask), run by bash (for its
    $(hostname)) in a process group of its own."""
    command = command.replace("dask ", f"{shlex.quote(sys.executable)} -m dask ", 1)
    with log.open("w") as out:
        return subprocess.Popen(
            ["bash", "-c", f"exec {command}"],
            cwd=folder,
            stdout=out,
            stderr=subprocess.STDOUT,
            env=env,
            start_new_session=True,
        )


def make_certificates(folder, ca: str, names) -> None:
    """Another CA and certificates it signed, as the page makes its own."""
    days = "30"
    run = {"cwd": folder, "check": True, "capture_output": True}
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", days,
                    "-keyout", f"{ca}.key", "-out", f"{ca}.pem", "-subj", f"/CN=blurlab {ca}"],
                   **run)  # fmt: skip
    for name in names:
        subprocess.run(
            [
                "openssl",
                "req",
                "-newkey",
                "rsa:2048",
                "-nodes",
                "-keyout",
                f"{name}.key",
                "-out",
                f"{name}.csr",
                "-subj",
                f"/OU=client/CN=blurlab {name}",
            ],
            **run,
        )
        subprocess.run(["openssl", "x509", "-req", "-in", f"{name}.csr", "-CA", f"{ca}.pem",
                        "-CAkey", f"{ca}.key", "-CAcreateserial", "-days", days,
                        "-out", f"{name}.pem"], **run)  # fmt: skip


@pytest.fixture(scope="module")
def tls_cluster(tmp_path_factory):
    """(tls:// address, folder, process groups) of the page's TLS scheduler and workers."""
    folder = tmp_path_factory.mktemp("tls_cluster")
    port = free_port()
    for command in documented("openssl ", port):
        subprocess.run(shlex.split(command), cwd=folder, check=True, capture_output=True)
    make_certificates(folder, "rogue_ca", ("rogue",))
    env = {**os.environ, "BLURLAB_DEVICE": CLI_DEVICE}
    processes = []
    try:
        (command,) = documented("dask scheduler ", port)
        processes.append(start_documented(command, folder, folder / "scheduler.log", env))
        wait_for_file(folder / "scheduler.json", processes[-1], folder / "scheduler.log")
        address = json.loads((folder / "scheduler.json").read_text())["address"]
        (command,) = documented("dask worker ", port)
        processes.append(start_documented(command, folder, folder / "worker.log", env))
        client = scheduler.scheduler_client(address, *(folder / n for n in CLIENT_FILES),
                                            connect_timeout_s=START_TIMEOUT_S)  # fmt: skip
        with client:
            client.wait_for_workers(2, timeout=START_TIMEOUT_S)
        yield address, folder, processes
    finally:
        for process in reversed(processes):
            stop_group(process)


CLIENT_FILES = ("ca.pem", "client.pem", "client.key")
NODE_FILES = ("ca.pem", "node.pem", "node.key")


def group_pids(processes) -> set[int]:
    """The processes of the given process groups (the workers are the nanny's children)."""
    groups = {process.pid for process in processes}
    pids = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) in groups:
            pids.add(int(stat.parent.name))
    return pids


def blurlab_sweep(folder, out: str, *options: str, device=()) -> subprocess.CompletedProcess:
    """`blurlab [device] sweep CONFIG [options]` in `folder`, into out.csv."""
    config = folder / f"{out}.toml"
    config.write_text(TOML.replace("{out}", (folder / f"{out}.csv").as_posix()))
    return subprocess.run(
        [sys.executable, "-m", "blurlab", *device, "sweep", str(config), *options],
        capture_output=True,
        text=True,
        timeout=SWEEP_TIMEOUT_S,
        cwd=folder,
        env={**os.environ, "BLURLAB_DEVICE": CLI_DEVICE},
    )


def without_timings(table: pd.DataFrame) -> pd.DataFrame:
    columns = [c for c in table.columns if not c.startswith("ms_") and c != "total_ms"]
    return table[sorted(columns)].sort_values("identity").reset_index(drop=True)


def test_the_documented_cluster_listens_on_loopback_only(tls_cluster):
    address, folder, processes = tls_cluster
    assert address.startswith("tls://127.0.0.1:")
    (check,) = documented("ss ", 0)
    listing = subprocess.run(["bash", "-c", check], capture_output=True, text=True, timeout=30)
    ours = group_pids(processes)
    listeners = []
    for line in listing.stdout.splitlines():
        pids = {int(pid) for pid in re.findall(r"pid=(\d+)", line)}
        if pids & ours:
            listeners.append(line.split()[3])  # State Recv-Q Send-Q Local:Port ...
    # the scheduler's port and HTTP endpoints; each of two workers and its nanny: port and HTTP
    assert len(listeners) >= 6, listing.stdout
    exposed = [a for a in listeners if not a.startswith(("127.", "[::1]:"))]
    assert not exposed, f"listening beyond loopback: {exposed}\n{listing.stdout}"


def test_a_sweep_through_tls_gives_the_rows_of_a_local_sweep(tls_cluster):
    address, folder, _ = tls_cluster
    (command,) = documented("blurlab sweep ", int(address.rsplit(":", 1)[1]))
    options = shlex.split(command)[3:]  # blurlab sweep my_sweep.toml OPTIONS
    assert options[:2] == ["--scheduler", address]
    remote = blurlab_sweep(folder, "tls", *options)
    assert remote.returncode == 0, (remote.stdout + remote.stderr)[-4000:]
    local = blurlab_sweep(folder, "local", device=("--device", CLI_DEVICE))
    assert local.returncode == 0, (local.stdout + local.stderr)[-4000:]
    got, expected = pd.read_csv(folder / "tls.csv"), pd.read_csv(folder / "local.csv")
    assert len(got) == len(SCENES) * 2
    pd.testing.assert_frame_equal(without_timings(got), without_timings(expected), check_exact=True)


def test_the_workers_node_certificate_is_refused_as_a_client(tls_cluster):
    address, folder, _ = tls_cluster
    node = bl.scheduler(address, *(folder / n for n in NODE_FILES), connect_timeout_s=20)
    with pytest.raises(PermissionError, match="OU=node.*OU=client"):
        node.connect()
    # nor may it ask the scheduler anything through Dask's RPC without registering
    import asyncio

    from distributed.core import rpc

    security = scheduler.tls_security(*(folder / n for n in NODE_FILES))

    async def ask():
        async with rpc(address, connection_args=security.get_connection_args("client")) as r:
            return await r.ncores()

    with pytest.raises(PermissionError, match="refuses 'ncores'"):
        asyncio.run(asyncio.wait_for(ask(), REFUSED_TIMEOUT_S))


def test_a_client_without_the_certificate_is_refused(tls_cluster):
    address, folder, _ = tls_cluster
    from distributed import Client

    # a certificate another CA signed
    rogue = scheduler.tls_security(*(folder / n for n in ("ca.pem", "rogue.pem", "rogue.key")))
    with pytest.raises((OSError, TimeoutError)):
        Client(address, security=rogue, timeout=REFUSED_TIMEOUT_S)
    # no TLS at all: the message says the port speaks TLS
    plain = address.replace("tls://", "tcp://")
    with pytest.raises(ConnectionError, match="speaks TLS; give its tls:// address"):
        bl.scheduler(plain, connect_timeout_s=3).connect()
    # blurlab sweep says what is missing, and so does bl.sweep, in the same words
    bare = blurlab_sweep(folder, "bare", "--scheduler", address)
    assert bare.returncode != 0 and "--tls-ca, --tls-cert and" in bare.stderr
    with pytest.raises(ValueError, match="give tls_ca, tls_cert and tls_key") as python_error:
        bl.sweep(None, SCENES, {GATHER: {"taps": [2]}}, size=SIZE, cluster=address)
    assert str(python_error.value).removeprefix("blurlab: ") in bare.stderr


def test_an_unreachable_scheduler_is_reported_within_the_connect_timeout():
    assert scheduler.CONNECT_TIMEOUT_S <= 10
    start = time.monotonic()
    with pytest.raises(TimeoutError, match="no Dask scheduler answered .* within 2 s"):
        bl.scheduler(f"tcp://127.0.0.1:{free_port()}", connect_timeout_s=2).connect()
    assert time.monotonic() - start < 2 + scheduler.TLS_PROBE_S + 5
    with pytest.raises(ValueError, match="connect time-out"):
        bl.scheduler("tcp://127.0.0.1:1", connect_timeout_s=0)


def test_a_plain_tcp_scheduler_elsewhere_gets_a_warning_naming_the_risk():
    with pytest.warns(UserWarning, match="anyone who can reach its port can run code"):
        scheduler.warn_if_exposed("tcp://10.1.2.3:8786")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for local in ("tcp://127.0.0.1:8786", "tcp://localhost:8786", "tcp://[::1]:8786"):
            scheduler.warn_if_exposed(local)
        scheduler.warn_if_exposed("tls://10.1.2.3:8786")


def test_a_local_cluster_listens_on_loopback_only():
    with pytest.raises(ValueError, match="loopback only"):
        bl.local_cluster(1, host="0.0.0.0")
    with pytest.raises(ValueError, match="all three"):
        scheduler.scheduler_client("tls://127.0.0.1:1", tls_ca="ca.pem")
