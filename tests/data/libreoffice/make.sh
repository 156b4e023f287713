#!/bin/sh
# Regenerates the probe workbooks of tests/libreoffice_probes.rs (see its module doc):
# make.py writes NAME.xlsx in Excel's file spelling with openpyxl (no cached values), and
# LibreOffice recalculates each on load and saves it as NAME.lo.xlsx, whose cached values
# are the oracle. Run from this folder; needs python3-openpyxl and soffice (7.4 made these).
set -e
here=$(pwd)
tmp=$(mktemp -d)
mkdir -p "$tmp/user" "$tmp/out"
cat > "$tmp/user/registrymodifications.xcu" <<'XCU'
<?xml version="1.0" encoding="UTF-8"?>
<oor:items xmlns:oor="http://openoffice.org/2001/registry" xmlns:xs="http://www.w3.org/2001/XMLSchema" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="OOXMLRecalcMode" oor:op="fuse"><value>0</value></prop></item>
</oor:items>
XCU
python3 make.py "$here" "$@"
for f in ${*:-$(python3 make.py --list)}; do
    # A probe with a .fods beside it takes its values from that (the same cells in ODF's spelling).
    src="$here/$f.xlsx"
    [ -f "$here/$f.fods" ] && src="$here/$f.fods"
    soffice "-env:UserInstallation=file://$tmp" --headless --norestore --convert-to xlsx --outdir "$tmp/out" "$src" >/dev/null 2>&1
    mv "$tmp/out/$f.xlsx" "$here/$f.lo.xlsx"
done
rm -rf "$tmp"
