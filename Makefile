# The course's commands. `make lab` opens the course; `make test` checks all of it.
# Both build .venv from environment.txt first (again whenever environment.txt changes).

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
# Jupyter refuses to run as root unless told; containers and CI often are root.
ROOT_FLAG := $(if $(filter 0,$(shell id -u)),--allow-root)
# Fixed hash seed: the same set/dict order in every kernel, so outputs are deterministic.
export PYTHONHASHSEED := 0
# Let Python cache compiled modules (some containers and CI images set
# PYTHONDONTWRITEBYTECODE): without the cache pytest rewrites the asserts of every test
# module again in each of its processes, 3 s of each worker's start.
unexport PYTHONDONTWRITEBYTECODE

NOTEBOOKS := $(sort $(wildcard notebooks/*.ipynb))
NBVAL_OPTS := --nbval --nbval-current-env --nbval-sanitize-with tests/nbval_sanitize.cfg

.PHONY: help lab test test-lib test-notebooks test-browser test-portable execute bench bench-grade slides book student clean
.PHONY: assignments grade
.PHONY: lint lint-lib
.PHONY: slides-solutions handouts
.PHONY: pdf
.PHONY: check-test-system

help:
	@echo "make lab      open the course in JupyterLab (sets up .venv the first time)"
	@echo "make test     run every test: library, notebooks (strict nbval, then make test-portable), editions, browser"
	@echo "              (FRESH=1: also run the edition test files that passed before on the same files)"
	@echo "make test-lib          only the library and checker tests (fast)"
	@echo "make test-notebooks    only the notebooks, under strict nbval"
	@echo "make test-portable     strict nbval again with other BLAS kernels and without AVX2/AVX-512 loops"
	@echo "make test-browser      only the tests in Chromium: decks, book, JupyterLab"
	@echo "make execute  re-run every notebook in place, top to bottom in a fresh kernel"
	@echo "              (one: make execute NB=notebooks/01_hat_map_and_lemma.ipynb)"
	@echo "make bench    time so3lib's exp and log against scipy"
	@echo "make bench-grade  time make grade on a made-up class (STUDENTS=3 per assignment, BENCH_JOBS=2)"
	@echo "make lint     ruff on so3lib, tests, tools and the notebooks (part of make test)"
	@echo "make lint-lib ruff on so3lib, tests and tools (part of make test-lib)"
	@echo "make slides   a reveal.js deck per notebook in build/slides/ (presents offline)"
	@echo "make handouts a PDF of each deck, one page per slide with its figures, in build/handouts/"
	@echo "make slides-solutions  the decks with the worked solutions, build/slides-solutions/"
	@echo "make book     the course as a Jupyter Book, build/book/index.html (reads offline)"
	@echo "make pdf      the whole course as one PDF, build/course.pdf"
	@echo "make student  the notebooks without worked solutions, in build/student/"
	@echo "make assignments  nbgrader coursework from the notebooks, in build/coursework/"
	@echo "make grade SUBMITTED=DIR  autograde DIR/STUDENT/ASSIGNMENT/*.ipynb: build/grades.csv, feedback"
	@echo "              (DIR not in the course folder: build/coursework/DIR, e.g. SUBMITTED=submitted)"
	@echo "make clean    remove .venv, build/ and caches"

# Python 3.11.5 or newer: environment.txt pins soupsieve 4.1.2, which requires it (Debian
# 12's own python3 is 3.11.2).
$(STAMP): environment.txt pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11, 5) else "Python 3.11.5 or newer is needed; found " + sys.version.split()[0] + ". Set PYTHON=/path/to/python3.11.")'
	rm -rf $(VENV)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -r environment.txt
	touch $@

# JupyterLab for a learner. It serves notebooks/ and its URL (printed with the login token)
# opens 00_start_here.ipynb. tools/lab_config/ comes first on the config path: nbgrader's
# menus and server extensions off (`make assignments` and `make grade` run nbgrader
# themselves), the kernel's connection encrypted, no news or update checks.
LAB_CONFIG := $(CURDIR)/tools/lab_config
lab: $(STAMP)
	JUPYTER_CONFIG_PATH="$(LAB_CONFIG)$${JUPYTER_CONFIG_PATH:+:$$JUPYTER_CONFIG_PATH}" \
	$(BIN)/jupyter lab --ServerApp.ip=127.0.0.1 --ServerApp.root_dir=notebooks \
	    --LabApp.default_url=/lab/tree/00_start_here.ipynb \
	    --LabApp.app_settings_dir="$(LAB_CONFIG)/settings" $(ROOT_FLAG) $(LAB_ARGS)

# First the programs outside Python the tests use (tools/check_system.py: Chromium, npm,
# poppler-utils, fonts): each missing one is named with its Debian package; the tests that
# need it are skipped, or under CI the run stops. Then lint, every test with the notebooks
# under strict nbval, and the notebooks again under other processors' arithmetic.
# FRESH=1: redo the slow edition test files that passed whole before on the same files
# (tests/pass_record.py: decks, book, coursework, student edition, Binder, JupyterLab); a
# fresh clone, and CI, does anyway.
test: check-test-system $(STAMP) lint
	$(if $(FRESH),TEST_FRESH=1) $(BIN)/python -m pytest -n 2 --dist loadfile $(NBVAL_OPTS) tests $(NOTEBOOKS)
	@$(MAKE) --no-print-directory test-portable

check-test-system:
	@$(PYTHON) -m tools.check_system test

# The library and its checkers, without the editions (decks, book, coursework, student
# edition) and the browser: seconds rather than minutes.
# Nor the two tests that set up what a newcomer gets, each most of a minute: a Binder
# image's environment in a fresh venv, and `make lab` itself.
EDITION_TESTS = test_browser test_interactive test_slides test_book test_book_laptop test_book_phone test_book_pdf \
                test_assignments test_student_edition \
                test_grading_sandbox
SLOW_TESTS = tests/test_binder.py::test_binder_image_runs_a_notebook_from_another_folder \
             tests/test_newcomer.py::test_make_lab_is_a_learners_lab
test-lib: $(STAMP) lint-lib
	$(BIN)/python -m pytest -n 2 tests $(EDITION_TESTS:%=--ignore=tests/%.py) $(SLOW_TESTS:%=--deselect=%)

# ruff with the rules in pyproject.toml (defects, not style): the notebooks too for
# `make test`, the library's own code for `make test-lib`.
lint: $(STAMP)
	$(BIN)/ruff check so3lib tests tools notebooks

lint-lib: $(STAMP)
	$(BIN)/ruff check so3lib tests tools

test-notebooks: $(STAMP)
	$(BIN)/python -m pytest -n 2 --dist loadfile $(NBVAL_OPTS) $(NOTEBOOKS)

# Strict nbval twice more, with the arithmetic of other processors, so that a stored output
# that holds on one machine only shows up here: OpenBLAS's kernels for Sandy Bridge (AVX,
# no FMA), then NumPy's SIMD loops limited to its x86-64-v2 baseline (its AVX2 and AVX-512
# dispatch groups off; `numpy.show_runtime()` lists them). The machine's own
# OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE and NumPy settings are removed for both runs, so the
# result does not depend on them. Both run; the target fails if either does.
PORTABLE_ENV := env -u OPENBLAS_CORETYPE -u OPENBLAS_L2_SIZE -u NPY_DISABLE_CPU_FEATURES \
                -u NPY_ENABLE_CPU_FEATURES
NPY_NO_AVX2 := X86_V3 X86_V4 AVX512_ICL AVX512_SPR
NBVAL_RUN = $(BIN)/python -m pytest -n 2 --dist loadfile $(NBVAL_OPTS) $(NOTEBOOKS)
test-portable: $(STAMP)
	@status=0; \
	echo "== strict nbval with OpenBLAS's Sandy Bridge kernels: OPENBLAS_CORETYPE=Sandybridge"; \
	$(PORTABLE_ENV) OPENBLAS_CORETYPE=Sandybridge $(NBVAL_RUN) || status=1; \
	echo "== strict nbval with NumPy's AVX2 and AVX-512 loops off: NPY_DISABLE_CPU_FEATURES=\"$(NPY_NO_AVX2)\""; \
	$(PORTABLE_ENV) NPY_DISABLE_CPU_FEATURES="$(NPY_NO_AVX2)" $(NBVAL_RUN) || status=1; \
	exit $$status

# Only the tests that drive Chromium: decks, handouts, book and JupyterLab.
test-browser: $(STAMP)
	$(BIN)/python -m pytest -n 2 --dist loadfile tests/test_browser.py tests/test_slides.py tests/test_book.py \
	    tests/test_book_laptop.py tests/test_book_phone.py tests/test_book_pdf.py

# Timing metadata is dropped and consecutive prints merged into one output, so that
# re-executing an unchanged notebook leaves its file unchanged. NB=PATH runs that notebook
# only (or several: NB="PATH PATH"). The kernel's connection is encrypted (CurveZMQ), as
# in `make lab`, so it does not warn about plain TCP.
execute: $(STAMP)
	$(BIN)/jupyter nbconvert --to notebook --execute --inplace \
	    --ExecutePreprocessor.timeout=300 --ExecutePreprocessor.kernel_name=python3 \
	    --KernelManager.transport_encryption=auto \
	    --ExecutePreprocessor.record_timing=False \
	    --NotebookExporter.preprocessors=nbconvert.preprocessors.CoalesceStreamsPreprocessor \
	    $(or $(NB),$(NOTEBOOKS))

bench: $(STAMP)
	$(BIN)/python tests/benchmark.py

# `make grade`'s speed: a made-up class of STUDENTS honest notebooks per assignment graded
# with BENCH_JOBS workers (2), as seconds per notebook and minutes for 1,400 (target: within 60)
bench-grade: $(STAMP)
	$(BIN)/python -m tools.bench_grade --students $(or $(STUDENTS),3) --jobs $(or $(BENCH_JOBS),2)

# The other editions (tools/): each fetches reveal.js / MathJax from the npm registry the
# first time (into build/npm/) and rebuilds only what changed.
slides: $(STAMP)
	$(BIN)/python -m tools.slides

# The decks with the worked solutions, for after the coursework's deadline (a separate folder).
slides-solutions: $(STAMP)
	$(BIN)/python -m tools.slides --solutions

# One PDF page per slide, printed by Chromium through reveal's print view, offline; each page
# holds its slide's figures (a 3-D figure as a still), checked with pdfimages when present.
handouts: $(STAMP)
	$(BIN)/python -m tools.slides --handouts

# The repository the book's launch buttons (Binder, JupyterHub) and GitHub link point at,
# and the JupyterHub: `make book BOOK_REPOSITORY=https://github.com/ORG/REPO
# BOOK_JUPYTERHUB=https://hub.example.edu`; placeholders otherwise (tools/book.py, README).
BOOK_ARGS = $(if $(BOOK_REPOSITORY),--repository-url $(BOOK_REPOSITORY)) \
            $(if $(BOOK_JUPYTERHUB),--jupyterhub-url $(BOOK_JUPYTERHUB))

book: $(STAMP)
	$(BIN)/python -m tools.book $(BOOK_ARGS)

# The whole course as one PDF, build/course.pdf, printed from the book by Chromium; first
# a check that Chromium, pdftotext (poppler-utils), npm and the fonts are there.
pdf: $(STAMP)
	@$(PYTHON) -m tools.check_system pdf
	$(BIN)/python -m tools.book --pdf $(BOOK_ARGS)

student: $(STAMP)
	$(BIN)/python -m tools.student

# nbgrader coursework (tools/assignments.py): source/ generated from the notebooks' tags,
# release/ by nbgrader; the gradebook is build/coursework/gradebook.db.
assignments: $(STAMP)
	$(BIN)/python -m tools.assignments

# Autograde SUBMITTED/STUDENT_ID/ASSIGNMENT/NOTEBOOK.ipynb (tools/grade.py); a cell may run
# TIMEOUT seconds; JOBS notebooks at once. Writes build/grades.csv and build/coursework/feedback/.
SUBMITTED ?= build/coursework/submitted
TIMEOUT ?= 60
JOBS ?= 1
grade: $(STAMP)
	$(BIN)/python -m tools.grade $(SUBMITTED) --timeout $(TIMEOUT) --jobs $(JOBS) $(if $(FORCE),--force)

clean:
	rm -rf $(VENV) build .pytest_cache .hypothesis
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
