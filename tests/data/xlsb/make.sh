#!/bin/sh
# Regenerates every .xlsb of this folder (and its .formulas.tsv) from the Excel-saved .xlsx
# that SOURCES.tsv names under ../excel-corpus/ironcalc. Needs python3 with openpyxl 3.1 and
# xlwt 1.3 (`pip install openpyxl==3.1.5 xlwt==1.3.0`); CI needs neither, the files are vendored.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
corpus="$here/../excel-corpus/ironcalc"
while IFS="$(printf '\t')" read -r name source; do
    python3 "$here/make_xlsb.py" "$corpus/$source" "$here/$name.xlsb" "$here/$name.formulas.tsv"
done < "$here/SOURCES.tsv"
