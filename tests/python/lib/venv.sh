# Sourced by the read-back tests from the repository root: makes the virtual environment
# .venv with the packages of tests/python/requirements.txt on first use, and installs them
# again only when that list changes (a copy of it is kept in .venv), so a warm run does not
# ask PyPI at all.
if [ ! -x .venv/bin/python ]; then python3 -m venv .venv; fi
if ! cmp -s tests/python/requirements.txt .venv/requirements.txt; then
  .venv/bin/pip install -q -r tests/python/requirements.txt
  cp tests/python/requirements.txt .venv/requirements.txt
fi
