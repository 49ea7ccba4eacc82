"""card.html: a card as a page that needs nothing but its folder (no network; its one script,
the comparator's, is inline): the suite's identity, the device and clock, then per category a
table of the methods' figures and its images section (`category_images_html`, the one place
that shows a category's pictures)."""

from __future__ import annotations

import html

from ..studies import comparator
from ..studies.interactive import PAGE_STYLE

e = html.escape


def number(value, digits: int = 4) -> str:
    return "–" if value is None else f"{value:.{digits}g}"


def category_images_html(category: str, pictures: dict | None, look: str = "") -> str:
    """A category's images section: the reference and each method's output on the category's
    first scene, side by side, then `look`, the comparator of the same outputs
    (blurlab.studies.comparator). `pictures`: {"scene": label, "images": {label: relative PNG
    path}} (blurlab.suite.run), or None where none were made (a cluster's rows, or
    pictures=False)."""
    if not pictures:
        return ""
    parts = [
        f"<h3>{e(category)}: {e(pictures['scene'])}</h3><div class='gallery'>",
        *(
            f"<figure><img src='{e(src)}' alt='{e(label)}'><figcaption>{e(label)}</figcaption>"
            "</figure>"
            for label, src in pictures["images"].items()
        ),
        "</div>",
        look,
    ]
    return "\n".join(parts)


def _category_table(entry: dict) -> str:
    methods = entry["methods"]
    metrics = list(next(iter(methods.values()))["metrics"])
    head = (
        "<tr><th>method</th>"
        + "".join(f"<th>{e(m)} median [95 % interval]</th>" for m in metrics)
        + "<th>rank among built-ins</th><th>win rate</th><th>against</th><th>ms</th></tr>"
    )
    rows = []
    for name, f in methods.items():
        cells = "".join(
            f"<td>{number(v['median'])} [{number(v['low'])}, {number(v['high'])}]</td>"
            for v in f["metrics"].values()
        )
        rows.append(
            f"<tr><td>{e(name)}</td>{cells}<td>{f['rank']} of {f['of']}</td>"
            f"<td>{100 * f['win_rate']:.0f} %</td><td>{e(f['versus'])}</td>"
            f"<td>{number(f['ms'])}</td></tr>"
        )
    return f"<table>{head}{''.join(rows)}</table>"


def card_html(card: dict, looks: dict | None = None) -> str:
    """The page of a card (blurlab.suite.run's dict, as card.json holds it); `looks`: each
    category's comparator (HTML), written with the card."""
    looks = looks or {}
    suite, device, images = card["suite"], card["device"], card.get("images", {})
    parts = [
        "<!doctype html><meta charset='utf-8'><title>blurlab suite card</title>",
        f"<style>{PAGE_STYLE}td:first-child{{text-align:left}}"
        ".gallery img{image-rendering:pixelated}</style>",
        f"<h1>blurlab suite v{suite['version']} ({e(suite['preset'])}): "
        f"{e(', '.join(card['methods']))}</h1>",
        f"<p>suite hash <code>{e(suite['hash'])}</code> · device <b>{e(device['renderer'])}</b>"
        f" ({e(device['device'])}, clock {e(device['clock'])}) · {e(card['date'])} · "
        f"blurlab {e(card['blurlab_version'])} · data: <a href='card.json'>card.json</a></p>",
        "<p>Each figure is the median over the category's scenes (over its frames for "
        "sequences) with its 95 % bootstrap interval (docs/spec.md §24.3). The rank is among "
        f"the {len(card['field'])} built-in methods by the category's first metric; the win "
        "rate is the share of scenes on which the method beats the best other built-in "
        "method (ties count half); ms is the median GPU time per frame on this device.</p>",
    ]
    for name, entry in card["categories"].items():
        parts.append(f"<h2>{e(name)}</h2><p>{e(entry['doc'])}.</p>")
        if entry["status"] != "measured":
            parts.append(f"<p><b>skipped</b>: {e(entry['reason'])}.</p>")
            continue
        settings = suite["definition"]["categories"][name]
        w, h = settings["size"]
        parts.append(
            f"<p>{len(entry['scenes'])} scene(s) at {w}×{h}; reference N = "
            f"{settings['reference']['samples']}; metrics {e(', '.join(settings['metrics']))} "
            f"(ranked by {e(entry['primary'])}).</p>"
        )
        parts.append(_category_table(entry))
        parts.append(category_images_html(name, images.get(name), looks.get(name, "")))
    if any(looks.values()):
        parts.append(comparator.assets_html())
    return "\n".join(parts) + "\n"
