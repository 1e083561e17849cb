"""pytest set-up of the tests of the package granhydro: the package is imported from
this checkout (tools/granhydro_py), whatever PYTHONPATH says."""
import os
import sys

TESTS = os.path.dirname(os.path.realpath(__file__))
PACKAGE_ROOT = os.path.dirname(TESTS)        # tools/granhydro_py
TOOLS = os.path.dirname(PACKAGE_ROOT)        # tools
REPO = os.path.dirname(TOOLS)

sys.path.insert(0, PACKAGE_ROOT)
sys.path.insert(0, TESTS)  # solver_files
