"""The documentation site: it builds with no warning, its generated CLI page is current, and its
pages say what is true now (docs/spec.md sections, not an issue tracker's numbers)."""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from method_picks import pick

import blurlab
from blurlab import cli_reference
from blurlab.docs_link import DOCS_URL_VARIABLE, docs_url

ROOT = Path(__file__).resolve().parents[1]
# A quick method for the small study these tests write: a gather with a few taps.
CHEAP = pick(params=("taps",))


def test_cli_page_is_current():
    """docs/cli.md is `python -m blurlab.cli_reference`'s output: every subcommand and option."""
    text = (ROOT / "docs" / "cli.md").read_text()
    assert text == cli_reference.markdown(), (
        "docs/cli.md is out of date: regenerate it with "
        "`python -m blurlab.cli_reference > docs/cli.md`"
    )


def test_cli_page_lists_every_subcommand_and_option():
    text = cli_reference.markdown()
    parser = cli_reference.build_parser()
    for name, _help, sub in cli_reference.subcommands(parser):
        assert f"## blurlab {name}\n" in text
        for option in cli_reference.arguments(sub):
            for flag in option.option_strings:
                assert f"`{flag}" in text, (name, flag)


@pytest.mark.skipif(importlib.util.find_spec("mkdocs") is None, reason="mkdocs not installed")
def test_site_builds_strict(ctx, monkeypatch, tmp_path):
    """`mkdocs build --strict`, as `make docs` runs it, on a copy of the docs with the example
    report made first (small here): a broken link, a page missing from the nav or a docstring
    mkdocstrings cannot read fails here."""
    from blurlab.studies.study import run_study

    source = tmp_path / "source"
    shutil.copytree(ROOT / "docs", source / "docs", ignore=shutil.ignore_patterns("example-report"))
    shutil.copy(ROOT / "mkdocs.yml", source)
    (source / "tools").symlink_to(ROOT / "tools")
    (source / "python").symlink_to(ROOT / "python")
    monkeypatch.setenv(DOCS_URL_VARIABLE, "..")
    run_study(
        ctx,
        ["fan"],
        size=(32, 18),
        out=source / "docs" / "example-report",
        grids={CHEAP: {}},
        progress=False,
    )
    site = tmp_path / "site"
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=source,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-4000:]
    assert (site / "api" / "context.html").is_file()
    # The example report is part of the site, and its docs link leads back into it.
    report = (site / "example-report" / "report.html").read_text()
    assert "href='../study.html'" in report and (site / "study.html").is_file()
    # Offline: no page loads a script, a style sheet or a font from elsewhere.
    loads = re.compile(r"<(?:script|link)\b[^>]*(?:src|href)=[\"']?(?:https?:)?//", re.IGNORECASE)
    remote = [
        str(page.relative_to(site))
        for page in site.rglob("*.html")
        if "example-report" not in page.parts and loads.search(page.read_text())
    ]
    assert not remote, remote


def test_docs_cite_spec_sections_not_issue_numbers():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    cited = [
        f"{page.relative_to(ROOT)}:{number}: {line.strip()}"
        for page in pages
        for number, line in enumerate(page.read_text().splitlines(), 1)
        if re.search(r"\bissues? ?#?[0-9]+", line, re.IGNORECASE)
    ]
    assert not cited, "cite docs/spec.md sections instead:\n" + "\n".join(cited)


def test_report_links_to_the_docs(monkeypatch, tmp_path):
    """The study report's link: the configured site, else the source checkout's own pages."""
    monkeypatch.setenv(DOCS_URL_VARIABLE, "https://example.org/blurlab/")
    assert docs_url("study") == "https://example.org/blurlab/study.html"
    monkeypatch.delenv(DOCS_URL_VARIABLE)
    local = docs_url("study")
    # Run from this checkout its pages; installed elsewhere (as the GPU run installs it) none.
    if (Path(blurlab.__file__).resolve().parents[2] / "mkdocs.yml").is_file():
        assert local.startswith("file:")
        assert local.endswith(("site/study.html", "docs/study.md"))
        with pytest.raises(ValueError, match="no docs page"):
            docs_url("no_such_page")
    else:
        assert local is None


def test_report_without_docs_to_link_names_the_pages(ctx, monkeypatch, tmp_path):
    """An installed wheel carries no docs (docs_url gives None): the report still writes, and
    names the pages where it would link them (this crashed `blurlab study` from a wheel)."""
    import blurlab.docs_link as docs_link
    from blurlab.studies.study import run_study

    monkeypatch.setattr(docs_link, "docs_url", lambda page: None)
    assert (
        docs_link.docs_anchor("study", "the docs") == "the docs (docs/study.md in blurlab's source)"
    )
    report = run_study(
        ctx, ["fan"], size=(32, 18), out=tmp_path, grids={CHEAP: {}}, progress=False
    ).read_text()
    assert "docs/metrics.md in blurlab's source" in report
    assert "docs/study.md in blurlab's source" in report
    assert "href='None'" not in report


def test_files_cite_the_architecture_page_not_a_missing_design_file():
    """docs/architecture.md holds the architecture; no file cites a DESIGN.md the repository
    does not have."""
    folders = ("python", "src", "tests", "docs", "shaders", "benchmarks", "tools")
    suffixes = {".py", ".md", ".h", ".cpp", ".glsl", ".comp", ".sh", ".yml", ".toml"}
    files = [ROOT / "README.md", ROOT / "mkdocs.yml", ROOT / "pyproject.toml"]
    files += [p for f in folders for p in (ROOT / f).rglob("*") if p.suffix in suffixes]
    citing = [
        str(p.relative_to(ROOT))
        for p in files
        if p.is_file() and p.name != "test_docs.py" and "DESIGN.md" in p.read_text(errors="ignore")
    ]
    assert (ROOT / "docs" / "architecture.md").is_file()
    assert not citing, citing
