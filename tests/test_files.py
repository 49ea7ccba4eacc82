"""Files under failure: writes to places that cannot hold a file raise and leave nothing
behind; corrupt or truncated EXR, PNG and OBJ files raise a clear error. (Tests run as root
here, so read-only folders made with chmod would not deny a write: the paths below fail for
any user.)"""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl

IMAGE = np.linspace(0, 1, 8 * 8 * 4, dtype=np.float32).reshape(8, 8, 4)


@pytest.mark.parametrize("suffix", [".exr", ".png"])
def test_write_under_a_file_raises_and_leaves_nothing(tmp_path, suffix):
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("I am a file")
    with pytest.raises(OSError, match="not_a_folder"):
        bl.io.write(blocker / f"image{suffix}", IMAGE)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["not_a_folder"]


@pytest.mark.parametrize("path", ["/proc/blurlab.exr", "/proc/self/blurlab.png"])
def test_write_where_the_os_refuses_raises(path):
    with pytest.raises(OSError):
        bl.io.write(path, IMAGE)


def test_write_to_a_folder_path_raises(tmp_path):
    (tmp_path / "taken.exr").mkdir()
    with pytest.raises(OSError):
        bl.io.write(tmp_path / "taken.exr", IMAGE)
    assert [p.name for p in tmp_path.iterdir()] == ["taken.exr"]


def good_files(tmp_path):
    return {
        ".exr": bl.io.write(tmp_path / "good.exr", IMAGE).read_bytes(),
        ".png": bl.io.write(tmp_path / "good.png", IMAGE).read_bytes(),
    }


@pytest.mark.parametrize("suffix", [".exr", ".png"])
@pytest.mark.parametrize("keep", [0, 1, 8, 40, 0.5, 0.9])
def test_truncated_images_raise(tmp_path, suffix, keep):
    data = good_files(tmp_path)[suffix]
    size = int(len(data) * keep) if isinstance(keep, float) else keep
    path = tmp_path / f"cut{suffix}"
    path.write_bytes(data[:size])
    with pytest.raises(OSError, match="cut"):
        bl.io.read(path)


@pytest.mark.parametrize("suffix", [".exr", ".png"])
def test_corrupt_images_raise(tmp_path, suffix, rng):
    data = bytearray(good_files(tmp_path)[suffix])
    # Keep the header, scramble the pixel data behind it.
    start = len(data) // 3
    data[start:] = rng.integers(0, 256, len(data) - start, dtype=np.uint8).tobytes()
    path = tmp_path / f"bad{suffix}"
    path.write_bytes(bytes(data))
    try:
        image = bl.io.read(path)
    except OSError as error:
        assert "bad" in str(error)
        return
    # Some scrambled data still decodes (EXR's uncompressed lines): then it is an image.
    assert image.shape[:2] == (8, 8)


def test_a_folder_is_not_an_image(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        bl.io.read(tmp_path)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2", "at least 3"),  # truncated mid-face
        ("v 0 0 0\nv 1 0 0\nv 0 1", "fewer than 3"),  # truncated mid-vertex
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4", "refers to no element"),
        ("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3", "NaN or inf"),
        ("v 1e999 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3", "NaN or inf"),
        ("", "no faces"),
    ],
)
def test_broken_obj_files_raise(tmp_path, text, message):
    path = tmp_path / "broken.obj"
    path.write_text(text)
    with pytest.raises((OSError, ValueError), match=message) as info:
        bl.mesh.load(path)
    assert "broken" in str(info.value)


def test_binary_obj_raises(tmp_path):
    path = tmp_path / "binary.obj"
    path.write_bytes(b"v 0 0 0\n\xff\xfe\x00\x01garbage")
    with pytest.raises(OSError, match="binary.obj"):
        bl.mesh.load(path)
