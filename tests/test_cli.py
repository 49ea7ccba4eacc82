"""The command line: `blurlab info` and the demo that the README's main command runs."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import CLI_DEVICE
from method_picks import pick

import blurlab as bl
from blurlab import cli


def test_info_prints_json(capsys):
    assert cli.main(["info"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["context"]["device"] in ("gpu", "software")
    assert report["devices"] == bl.Context.devices()


def test_demo_renders_blurs_and_writes(tmp_path, capsys):
    assert cli.main(["demo", "--size", "160x90", "--out", str(tmp_path)]) == 0
    assert bl.io.read(tmp_path / "test_pattern.png").shape == (90, 160, 3)
    for name in bl.scenes.names():
        sharp = bl.io.read(tmp_path / f"{name}_sharp.png")
        blurred = bl.io.read(tmp_path / f"{name}_blurred.png")
        assert sharp.shape == blurred.shape == (90, 160, 4)
        gbuffer = bl.io.read(tmp_path / f"{name}_gbuffer.exr")
        assert gbuffer.shape == (90, 160, 7) and gbuffer.dtype == np.float32
    printed = capsys.readouterr().out
    assert "largest difference from NumPy" in printed and "teapot_pass" in printed


def test_bad_size_is_rejected():
    with pytest.raises(SystemExit):
        cli.main(["demo", "--size", "160by90"])


def run_cli(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "blurlab", *args], capture_output=True, text=True, cwd=cwd
    )


def test_a_closed_pipe_ends_the_command_quietly():
    """`blurlab methods | head -1`: the reader goes away; the command stops with no message and
    the status a shell shows for SIGPIPE, as Unix tools do."""
    child = subprocess.Popen(
        [sys.executable, "-m", "blurlab", "methods"], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    child.stdout.close()  # the reader is gone before the first line
    stderr = child.stderr.read()
    assert child.wait() == 141 and stderr == b"", stderr.decode()


def test_a_reader_gone_mid_listing_is_not_an_error(monkeypatch, capsys):
    class ClosedPipe:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(sys, "stdout", ClosedPipe())
    assert cli.main(["methods"]) == 141
    assert capsys.readouterr().err == ""


def assert_one_line_error(result, *fragments):
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("blurlab: error: "), result.stderr
    assert "Traceback" not in result.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


# A method with a `taps` parameter: "tap" is a near miss it refuses.
TAPPED = pick(params=("taps",))


@pytest.mark.parametrize(
    ("config", "fragments"),
    [
        ('scenes = ["fan"]\nmethodz = {}\n', ("methodz",)),
        ('scenes = ["no_such_scene"]\n', ("no_such_scene",)),
        ('scenes = ["fan"]\nmethods = {no_such_method = {}}\n', ("no_such_method",)),
        (
            f'scenes = ["fan"]\nmethods = {{{TAPPED} = {{tap = [3]}}}}\n',
            (TAPPED, "tap"),
        ),
        ('scenes = ["fan"]\nsize = [0, 90]\n', ("size",)),
    ],
    ids=["bad key", "unknown scene", "unknown method", "unknown parameter", "bad size"],
)
def test_user_errors_are_one_line_with_status_2(tmp_path, config, fragments):
    path = tmp_path / "sweep.toml"
    path.write_text(config)
    assert_one_line_error(run_cli("--device", CLI_DEVICE, "sweep", str(path)), *fragments)


def test_a_bad_size_argument_is_one_line_with_status_2():
    assert_one_line_error(run_cli("demo", "--size", "160by90"), "160by90")


def test_a_missing_config_file_is_one_line_with_status_2(tmp_path):
    assert_one_line_error(run_cli("sweep", str(tmp_path / "missing.toml")), "missing.toml")


def test_debug_shows_the_traceback(tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_text('scenes = ["no_such_scene"]\n')
    result = run_cli("--debug", "--device", CLI_DEVICE, "sweep", str(path))
    assert result.returncode != 0 and "Traceback" in result.stderr


def test_an_unknown_peer_is_one_line_with_status_2(tmp_path):
    result = run_cli("--device", CLI_DEVICE, "study", "--peers", "nope", "--out", str(tmp_path))
    assert_one_line_error(result, "unknown peers", "eevee")
    assert not (tmp_path / "results.csv").exists()  # refused before any work
