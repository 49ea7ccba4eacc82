"""The suite (docs/suite.md, docs/spec.md §26): the tiny preset gives a card for a method from
--methods-from and a built-in within 60 s; a rerun gives the same figures and hash, resuming
its rows; a changed reference definition, or changed reference or metric code, changes the
hash; cards of other suites are refused; bad input is refused with what is allowed."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import CLI_DEVICE
from method_picks import pick

import blurlab as bl
from blurlab.suite import compare, compare_text, content, load_card, run_suite
from blurlab.suite import definition as d

ASSETS = Path(__file__).resolve().parents[2] / "shared" / "assets" / "gltf"
ROOT = Path(__file__).resolve().parents[1]
# A one-frame built-in, carded beside a method folder's method (picked by its role, the same
# each run).
BUILTIN = pick(role="translucent_layer")


def blurlab(*args, cwd: Path) -> subprocess.CompletedProcess:
    env_path = str(Path(bl.__file__).parents[1])
    return subprocess.run(
        [sys.executable, "-m", "blurlab", "--device", CLI_DEVICE, *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env={**os.environ, "PYTHONPATH": env_path},
        timeout=600,
    )


def figures_of(card: dict, with_ms: bool) -> dict:
    """The card's figures by (category, method); without ms where they are not compared."""
    out = {}
    for name, entry in card["categories"].items():
        for who, f in entry.get("methods", {}).items():
            out[name, who] = {k: v for k, v in f.items() if with_ms or k != "ms"}
    return out


def test_tiny_card_for_a_method_folder_and_a_builtin_then_a_rerun(tmp_path):
    made = blurlab("new-method", "my_tent", "--out", "X", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    command = ["suite", "run", "--preset", "tiny", "--methods", "my_tent", BUILTIN]
    command += ["--methods-from", "X", "--out", "card"]
    start = time.perf_counter()
    ran = blurlab(*command, cwd=tmp_path)
    wall = time.perf_counter() - start
    assert ran.returncode == 0, ran.stdout + ran.stderr
    assert wall <= 60, f"the tiny preset for two methods took {wall:.1f} s"
    card = load_card(tmp_path / "card")
    assert list(card["methods"]) == ["my_tent", BUILTIN]
    assert card["methods"]["my_tent"]["builtin"] is False
    assert card["suite"] == {**content.suite_identity("tiny"), "definition": d.definition("tiny")}
    assert card["device"]["clock"] in ("gl_time_elapsed", "wall_glfinish")
    assert card["categories"]["authored"]["status"] == "skipped"  # no --assets given
    measured = [c for c in d.categories() if not c.needs_assets]
    for category in measured:
        entry = card["categories"][category.name]
        assert entry["status"] == "measured"
        for f in entry["methods"].values():
            for value in f["metrics"].values():
                assert value["low"] <= value["median"] <= value["high"]
            assert (
                1 <= f["rank"] <= f["of"] == len(card["field"]) + (f is entry["methods"]["my_tent"])
            )
            assert 0 <= f["win_rate"] <= 1 and f["versus"] in card["field"]
            assert f["ms"] > 0 and f["clock"] == card["device"]["clock"]
    page = (tmp_path / "card" / "card.html").read_text()
    assert "my_tent" in page and card["suite"]["hash"] in page
    for src in json.dumps(card).split('"images/')[1:]:  # no picture named that is not there
        assert (tmp_path / "card" / "images" / src.split('"')[0]).is_file()
    assert (tmp_path / "card" / "images" / "opaque" / "my_tent.png").is_file()
    # each measured picture category has its comparator, with its pictures beside the page
    for name in card["images"]:
        assert f"id='look-{name}'" in page or f'id="look-{name}"' in page, name
    looked = re.findall(r"(?:look|images)/[\w./-]+\.png", page)
    assert looked and all((tmp_path / "card" / src).is_file() for src in looked)
    # an SDR category's comparator shows the card's own pictures; only HDR ones have their own
    hdr = {c.name for c in d.categories() if bl.metrics.get(c.primary).hdr}
    for name in card["images"]:
        assert (f"look/{name}_" in page) == (name in hdr), name
    assert "images/opaque/my_tent.png" in looked and "images/opaque/my_tent_error.png" in looked

    # A rerun: one category's rows removed are evaluated again, the rest are read back; a
    # sequence row cut short by a crash is dropped.
    (tmp_path / "card" / "rows" / "opaque.csv").unlink()
    sequence_rows = tmp_path / "card" / "rows" / "sequences.jsonl"
    whole = sequence_rows.read_text()
    sequence_rows.write_text(whole + '{"key": "cut sh')
    again = blurlab(*command, cwd=tmp_path)
    assert again.returncode == 0, again.stdout + again.stderr
    second = load_card(tmp_path / "card")
    assert second["suite"]["hash"] == card["suite"]["hash"]
    assert second["run"]["resumed_rows"] > 0
    assert sequence_rows.read_text() == whole  # every sequence run read back, none made again
    assert figures_of(second, with_ms=False) == figures_of(card, with_ms=False)
    same_ms = {k: v for k, v in figures_of(card, True).items() if k[0] != "opaque"}
    assert {k: v for k, v in figures_of(second, True).items() if k[0] != "opaque"} == same_ms

    # A card for one method with the field's rows taken from that card: nothing evaluated
    # again, the same figures; a taken file's rows keep their keys (the next run resumes).
    mine = ["suite", "run", "--preset", "tiny", "--methods", "my_tent", "--methods-from", "X"]
    taken = blurlab(*mine, "--out", "mine", "--field-from", "card", cwd=tmp_path)
    assert taken.returncode == 0, taken.stdout + taken.stderr
    one = load_card(tmp_path / "mine")
    assert one["run"]["rows_taken_from_field_card"] > 0
    for rows in (tmp_path / "card" / "rows").iterdir():  # no row made anew
        assert (tmp_path / "mine" / "rows" / rows.name).read_bytes() == rows.read_bytes()
    assert one["suite"]["hash"] == card["suite"]["hash"]
    mine_figures = {k: v for k, v in figures_of(second, True).items() if k[1] == "my_tent"}
    assert figures_of(one, True) == mine_figures
    refused = blurlab(*mine, "--out", "none", "--field-from", "nowhere", cwd=tmp_path)
    assert refused.returncode != 0 and "no rows/ folder" in refused.stderr

    # compare: cards of one suite side by side; a card of another suite is refused.
    shutil.copytree(tmp_path / "card", tmp_path / "copy", ignore=shutil.ignore_patterns("rows"))
    tables = compare([tmp_path / "card", tmp_path / "copy"])
    assert set(tables) == {c.name for c in measured}
    assert len(tables["opaque"]) == 4  # two methods on each of two cards
    text = compare_text([tmp_path / "card", tmp_path / "copy" / "card.json"])
    assert "## sequences" in text and "note:" not in text
    moved = {**json.loads((tmp_path / "copy" / "card.json").read_text()), "field_digest": "f" * 16}
    (tmp_path / "moved.json").write_text(json.dumps(moved))
    text = compare_text([tmp_path / "card", tmp_path / "moved.json"])
    assert "note: the cards' built-in methods ran other code" in text
    other = json.loads((tmp_path / "copy" / "card.json").read_text())
    other["suite"]["hash"], other["suite"]["parts"]["definition"] = "0" * 16, "1" * 16
    (tmp_path / "copy" / "card.json").write_text(json.dumps(other))
    refused = blurlab("suite", "compare", "card", "copy", cwd=tmp_path)
    assert refused.returncode == 2
    assert card["suite"]["hash"] in refused.stderr and "0" * 16 in refused.stderr
    assert "differ in: definition" in refused.stderr


def test_a_changed_reference_definition_or_code_changes_the_hash(tmp_path, monkeypatch):
    first = content.suite_identity("tiny")
    assert content.suite_identity("tiny") == first  # the same definition, the same hash
    assert content.suite_identity("software")["hash"] != first["hash"]
    # the reference's N of one category
    opaque = d.category("opaque")
    tiny = dataclasses.replace(opaque.presets["tiny"], reference_samples=64)
    changed = dataclasses.replace(opaque, presets={**opaque.presets, "tiny": tiny})
    others = tuple(changed if c is opaque else c for c in d.CATEGORIES)
    monkeypatch.setattr(d, "CATEGORIES", others)
    moved = content.suite_identity("tiny")
    assert moved["hash"] != first["hash"]
    assert moved["parts"]["definition"] != first["parts"]["definition"]
    assert moved["parts"]["scenes"] == first["parts"]["scenes"]
    monkeypatch.undo()
    # the reference's code, and a shader it runs: a copy of the files hashes the same, an
    # edit to either does not
    package, shaders = tmp_path / "blurlab", tmp_path / "shaders"
    for name, path in content.code_files():
        copy = tmp_path / name
        copy.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(path, copy)
    assert content.code_digest(package, shaders) == first["parts"]["code"]
    with (package / "core" / "references.py").open("a") as f:
        f.write("\n# another reference\n")
    edited = content.code_digest(package, shaders)
    assert edited != first["parts"]["code"]
    with (shaders / "passes" / "accumulate.comp").open("a") as f:
        f.write("\n// another sum\n")
    assert content.code_digest(package, shaders) not in (edited, first["parts"]["code"])
    monkeypatch.setattr(content, "code_digest", lambda: edited)
    assert content.suite_identity("tiny")["hash"] != first["hash"]


@pytest.mark.skipif(not ASSETS.is_dir(), reason=f"no sample models in {ASSETS}")
def test_the_authored_files_are_pinned_by_their_digests(tmp_path):
    authored = d.category("authored")
    paths, why = d.authored_paths(authored, "software", ASSETS)
    assert why is None and len(paths) == len(d.AUTHORED_FILES)
    assert d.authored_paths(authored, "tiny", None)[1].startswith("no assets folder")
    assert "lacks" in d.authored_paths(authored, "tiny", tmp_path)[1]
    name = authored.presets["tiny"].scenes[0]
    (tmp_path / name).parent.mkdir(parents=True)
    (tmp_path / name).write_bytes((ASSETS / name).read_bytes() + b" ")
    with pytest.raises(ValueError, match="not the .* that suite v1 pins"):
        d.authored_paths(authored, "tiny", tmp_path)


def test_bad_input_is_refused_with_what_is_allowed(ctx, tmp_path):
    with pytest.raises(ValueError, match="preset must be one of tiny, software, gpu"):
        run_suite(ctx, tmp_path / "a", [BUILTIN], "huge")
    with pytest.raises(ValueError, match="no method 'nope'"):
        run_suite(ctx, tmp_path / "a", [BUILTIN, "nope"], "tiny")
    sequence = pick(kind="sequence")
    with pytest.raises(ValueError, match=f"{sequence} blends frames itself"):
        run_suite(ctx, tmp_path / "a", [sequence], "tiny")
    with pytest.raises(ValueError, match="is not a folder"):
        run_suite(ctx, tmp_path / "a", [BUILTIN], "tiny", assets=tmp_path / "none")
    assert not (tmp_path / "a").exists()  # refused before anything is written
    with pytest.raises(ValueError, match="no category 'glass'"):
        d.category("glass")
    (tmp_path / "card.json").write_text('{"format": 1}')
    with pytest.raises(ValueError, match="lacks 'suite'"):
        load_card(tmp_path)
    (tmp_path / "card.json").write_text("[1, 2")
    with pytest.raises(ValueError, match="not a card's JSON"):
        load_card(tmp_path / "card.json")
    card = {"format": 1, "suite": {"hash": "a"}, "device": {}, "date": "", "methods": {}}
    (tmp_path / "card.json").write_text(
        json.dumps({**card, "categories": {"opaque": {"methods": {"x": {}}}}})
    )
    shutil.copy(tmp_path / "card.json", tmp_path / "other.json")
    with pytest.raises(ValueError, match="lacks a figure"):
        compare([tmp_path / "card.json", tmp_path / "other.json"])
    with pytest.raises(ValueError, match="at least two cards"):
        compare([tmp_path])


def test_the_suite_page_shows_the_definition():
    """docs/suite.md's settings table is the definition's own (blurlab.suite.definition)."""
    page = (ROOT / "docs" / "suite.md").read_text()
    assert d.markdown_table() in page, (
        "docs/suite.md: paste blurlab.suite.definition.markdown_table()"
    )
