"""`blurlab recommend` for every built-in scene at budgets of 0.1, 1 and 10 ms: the answer and
the fastest configuration, in the table docs/recommend.md shows.

    python benchmarks/recommend.py [--device gpu] [--size 1920x1080]
"""

from __future__ import annotations

import argparse

import blurlab as bl

from common import describe, open_context, save

BUDGETS_MS = (0.1, 1.0, 10.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "size": args.size, "answers": []}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}")
    print("\n| scene | budget | recommended | ms | PSNR | SSIM |")
    print("|---|---|---|---|---|---|")
    for scene in bl.scenes.names():
        for budget in BUDGETS_MS:
            answer = bl.recommend(ctx, scene, size, budget_ms=budget)
            entry = {"scene": scene, "budget_ms": budget, "answer": str(answer)}
            if answer.row is None:
                print(f"| {scene} | {budget:g} ms | {answer} | | | |")
            else:
                entry.update(method=answer.method, params=answer.params, row=answer.row)
                print(
                    f"| {scene} | {budget:g} ms | {answer.method} {answer.params} | "
                    f"{answer.row['total_ms']:.3g} | {answer.row['psnr']:.2f} | "
                    f"{answer.row['ssim']:.4f} |"
                )
            record["answers"].append(entry)
    save(args.json, record)


if __name__ == "__main__":
    main()
