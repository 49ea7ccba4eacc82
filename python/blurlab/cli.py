"""The ``blurlab`` command: ``blurlab info`` and ``blurlab demo``."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path


def parse_size(text: str) -> tuple[int, int]:
    """'640x360' -> (640, 360)."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 640x360, not {text!r}") from None
    if width < 1 or height < 1:
        raise argparse.ArgumentTypeError(f"size must be positive, not {text!r}")
    return width, height


def parse_device(text: str) -> str | int:
    return int(text) if text.isdigit() else text


def _info(args) -> int:
    from .context import Context

    ctx = Context(args.device)
    print(json.dumps({"devices": Context.devices(), "context": ctx.info()}, indent=2))
    return 0


def _demo(args) -> int:
    import numpy as np

    from . import io
    from .context import Context

    ctx = Context(args.device)
    info = ctx.info()
    print(f"device: {info['device']} ({info['renderer']}, {info['version']})")
    width, height = args.size
    pattern = ctx.empty((height, width, 4), "float32")
    program = ctx.program("util/test_pattern.comp")
    with ctx.timer() as timing:
        program.run((width, height), images=[(pattern, "write")], uniforms={"seed": args.seed})
    image = pattern.download()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    io.write(out / "test_pattern.exr", image)
    io.write(out / "test_pattern.png", image[..., :3])
    print(f"test pattern {width}x{height}: {timing.ms:.3f} ms ({timing.clock})")
    print(f"wrote {out / 'test_pattern.exr'} and {out / 'test_pattern.png'}")
    print(f"mean rand (expect about 0.5): {float(np.mean(image[..., 3])):.4f}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="blurlab", description=__doc__)
    parser.add_argument(
        "--device",
        type=parse_device,
        default="auto",
        help="auto, gpu, software, or an EGL device index (default: auto)",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("info", help="print the EGL devices and the context's info as JSON")
    demo = sub.add_parser("demo", help="render a test pattern on the GPU and write EXR + PNG")
    demo.add_argument("--out", default="out/demo", help="output folder (default: out/demo)")
    demo.add_argument("--size", type=parse_size, default=(640, 360), help="WxH (default 640x360)")
    demo.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    return {"info": _info, "demo": _demo}[args.command](args)


if __name__ == "__main__":
    sys.exit(main())
