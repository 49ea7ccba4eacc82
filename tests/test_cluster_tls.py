"""A sweep through a TLS Dask cluster started from the command line (docs/distributed.md,
"Securing a cluster"): certificates made with openssl as the page shows, a `dask scheduler`
and a `dask worker` process (two workers) with TLS options on the loopback interface, and
`blurlab sweep --scheduler tls://... --tls-ca --tls-cert --tls-key`. Its rows equal a local
sweep's, bit for bit but for the pass times; a client whose certificate another CA signed,
one without TLS, and `blurlab sweep` without the certificates are refused."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings

import pandas as pd
import pytest
from conftest import CLI_DEVICE
from process_group import START_TIMEOUT_S, start_dask_cluster, stop_group

import blurlab as bl
from blurlab.studies import scheduler

pytest.importorskip("distributed")

SCENES = ["fan", "crossing"]
SIZE = (32, 18)
SWEEP_TIMEOUT_S = 300
REFUSED_TIMEOUT_S = 10
TOML = (
    f"scenes = {json.dumps(SCENES)}\nsize = {json.dumps(list(SIZE))}\nreference_samples = 8\n"
    'metrics = ["psnr", "ssim"]\nout = "{out}"\n[methods.gather_box]\ntaps = [2, 4]\n'
)


def openssl(folder, *arguments: str) -> None:
    subprocess.run(["openssl", *arguments], cwd=folder, check=True, capture_output=True)


def make_certificates(folder, ca: str = "ca", names=("node", "client")) -> None:
    """A CA (ca.pem, ca.key) and, signed by it, a certificate and key per name: the commands
    of docs/distributed.md, 'Securing a cluster'."""
    days = "30"
    openssl(folder, "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", days,
            "-keyout", f"{ca}.key", "-out", f"{ca}.pem", "-subj", f"/CN=blurlab {ca}")  # fmt: skip
    for name in names:
        openssl(folder, "req", "-newkey", "rsa:2048", "-nodes", "-keyout", f"{name}.key",
                "-out", f"{name}.csr", "-subj", f"/CN=blurlab {name}")  # fmt: skip
        openssl(folder, "x509", "-req", "-in", f"{name}.csr", "-CA", f"{ca}.pem", "-CAkey",
                f"{ca}.key", "-CAcreateserial", "-days", days, "-out", f"{name}.pem")  # fmt: skip


@pytest.fixture(scope="module")
def tls_cluster(tmp_path_factory):
    """(tls:// address, folder) of a TLS scheduler and two TLS workers, each started from the
    command line in a process group of its own."""
    folder = tmp_path_factory.mktemp("tls_cluster")
    make_certificates(folder)
    make_certificates(folder, ca="rogue_ca", names=("rogue",))
    pem = {name: str(folder / name) for name in ("ca.pem", "node.pem", "node.key")}
    tls = ["--protocol", "tls", "--tls-ca-file", pem["ca.pem"], "--tls-cert", pem["node.pem"]]
    tls += ["--tls-key", pem["node.key"]]
    env = {**os.environ, "BLURLAB_DEVICE": CLI_DEVICE}
    processes = []
    try:
        address = start_dask_cluster(folder, env, processes, tls)
        security = scheduler.tls_security(
            *(folder / name for name in ("ca.pem", "client.pem", "client.key"))
        )
        from distributed import Client

        with Client(address, security=security, timeout=START_TIMEOUT_S) as client:
            client.wait_for_workers(2, timeout=START_TIMEOUT_S)
        yield address, folder
    finally:
        for process in reversed(processes):
            stop_group(process)


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


def test_a_sweep_through_tls_gives_the_rows_of_a_local_sweep(tls_cluster):
    address, folder = tls_cluster
    assert address.startswith("tls://127.0.0.1:")
    tls = ["--tls-ca", "ca.pem", "--tls-cert", "client.pem", "--tls-key", "client.key"]
    remote = blurlab_sweep(folder, "tls", "--scheduler", address, *tls)
    assert remote.returncode == 0, (remote.stdout + remote.stderr)[-4000:]
    local = blurlab_sweep(folder, "local", device=("--device", CLI_DEVICE))
    assert local.returncode == 0, (local.stdout + local.stderr)[-4000:]
    got, expected = pd.read_csv(folder / "tls.csv"), pd.read_csv(folder / "local.csv")
    assert len(got) == len(SCENES) * 2
    pd.testing.assert_frame_equal(without_timings(got), without_timings(expected), check_exact=True)


def test_a_client_without_the_certificate_is_refused(tls_cluster):
    address, folder = tls_cluster
    from distributed import Client

    # a certificate another CA signed
    rogue = scheduler.tls_security(*(folder / n for n in ("ca.pem", "rogue.pem", "rogue.key")))
    with pytest.raises((OSError, TimeoutError)):
        Client(address, security=rogue, timeout=REFUSED_TIMEOUT_S)
    with pytest.raises((OSError, TimeoutError)):  # no TLS at all
        Client(address.replace("tls://", "tcp://"), timeout=REFUSED_TIMEOUT_S)
    # blurlab sweep says what is missing
    bare = blurlab_sweep(folder, "bare", "--scheduler", address)
    assert bare.returncode != 0 and "--tls-ca, --tls-cert and" in bare.stderr


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
