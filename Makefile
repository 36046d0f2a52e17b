# `make demo` and `make test` each create .venv when it is missing and install the project into it.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test test-setup lint docs clean

$(STAMP): pyproject.toml
	test -d $(VENV) || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,records,distributed,excel]'
	# compile the numba kernels now (once per install; an editable install does not ship them), not
	# during the first analysis or in each test worker
	$(BIN)/pounding warmup --all
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/pounding study examples/demo_study.toml -o reports/demo/results.nc
	$(BIN)/pounding report reports/demo/results.nc -o reports/demo
	$(BIN)/pounding ida examples/ida_fragility.toml -o reports/ida/ida.nc
	$(BIN)/pounding report reports/ida/ida.nc -o reports/ida

# The report tests open the HTML in headless Chromium and read the PDF with poppler-utils (Debian
# packages chromium, poppler-utils); installed here when missing and apt-get is usable (root).
test-setup:
	@command -v chromium >/dev/null && command -v pdftotext >/dev/null && command -v pdftoppm >/dev/null \
	  || (apt-get update && apt-get install -y chromium poppler-utils) \
	  || echo "warning: could not install chromium and poppler-utils; the report tests that need them will be skipped"

# After the tests: install pounding as a user would (plain `pip install .`, and -e with each extra alone)
# into throw-away venvs and run `pounding run` + read the NetCDF back (tests/install_check.py).
# The tests run in one worker process per core (pytest-xdist), each test module in one worker (loadscope:
# its module-scoped fixtures and cached references are computed once, not once per worker).
test: $(STAMP) test-setup
	$(BIN)/python -m pytest -q -n auto --dist loadscope
	$(BIN)/python tests/install_check.py

# The documentation site (user guide from the README, the case-file reference, the design, the API from
# the docstrings with their equations) into docs/_build/html; warnings are errors.
docs: $(STAMP)
	$(BIN)/python -m sphinx -b html -W --keep-going -q docs docs/_build/html
	@echo "written docs/_build/html/index.html"

lint: $(STAMP)
	$(BIN)/ruff check . && $(BIN)/ruff format --check .

clean:
	rm -rf $(VENV) .pytest_cache build *.egg-info docs/_build
