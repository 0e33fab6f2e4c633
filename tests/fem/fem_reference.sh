#!/usr/bin/env bash
# The finite-element reference (fem/): three small committed cases re-run with CalculiX and
# compared with fem/tables/ (fem/check_case.py states the tolerances). Exit 77 (skipped)
# when ccx is not installed.
exec python3 "$2/fem/check_case.py" "$1"
