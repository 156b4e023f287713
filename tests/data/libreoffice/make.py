#!/usr/bin/env python3
"""Probe workbooks for tests/libreoffice_probes.rs, in Excel's file spelling (openpyxl writes
the formulas verbatim, with no cached values). make.sh has LibreOffice recalculate them; its
values are the oracle. `make.py DIR` writes them; `make.py --list` names them."""
import sys
from openpyxl import Workbook
from openpyxl.worksheet.table import Table, TableStyleInfo
from openpyxl.worksheet.formula import ArrayFormula
from openpyxl.workbook.defined_name import DefinedName

out = sys.argv[1]
PROBES = ["tables", "three_d", "cse", "dates1904", "names", "iterate_converge", "iterate_capped", "text_formats",
          "errors", "engineering"]
if out == "--list":
    print(" ".join(PROBES))
    sys.exit(0)


def save(wb, name):
    wb.save(f"{out}/{name}.xlsx")


# ---------------------------------------------------------------- tables
def tables():
    wb = Workbook()
    d = wb.active
    d.title = "Parts Data"
    head = ["Part No", "Qty", "Unit Price", "Col'#", "[x]", "Line Total"]
    d.append(head)
    rows = [("a", 2, 1.5, 10, 100), ("b", 3, 2.25, 20, 200), ("c", 5, 0.5, 30, 300), ("d", 7, 4, 40, 400)]
    for i, r in enumerate(rows, start=2):
        d.append(list(r) + [f"=Parts[[#This Row],[Qty]]*Parts[[#This Row],[Unit Price]]"])
    # totals row (row 6)
    d["A6"] = "Total"
    d["B6"] = "=SUBTOTAL(109,Parts[Qty])"
    d["F6"] = "=SUBTOTAL(109,Parts[Line Total])"
    t = Table(displayName="Parts", ref="A1:F6", totalsRowCount=1)
    t.tableStyleInfo = TableStyleInfo(name="TableStyleMedium9", showRowStripes=True)
    t._initialise_columns()
    for c, h in zip(t.tableColumns, head):
        c.name = h
    t.tableColumns[0].totalsRowLabel = "Total"
    t.tableColumns[1].totalsRowFunction = "sum"
    t.tableColumns[5].totalsRowFunction = "sum"
    d.add_table(t)
    # formulas in the same sheet, outside the table (column H), this-row on rows 2..5
    d["H2"] = "=Parts[[#This Row],[Qty]]+1"
    d["H3"] = "=SUM(Parts[[#This Row],[Qty]:[Unit Price]])"
    d["H4"] = "=Parts[[#This Row],[Col'#]]"
    d["H5"] = "=Parts[[#This Row],['[x']]]"
    f = wb.create_sheet("Use")
    forms = [
        "=SUM(Parts[Qty])",
        "=SUM(Parts[[#Data],[Qty]])",
        "=Parts[[#Headers],[Unit Price]]",
        "=Parts[[#Totals],[Qty]]",
        "=ROWS(Parts[#All])",
        "=ROWS(Parts[#Data])",
        "=ROWS(Parts)",
        "=COLUMNS(Parts[#All])",
        "=COUNTA(Parts[#Headers])",
        "=ROWS(Parts[[#Headers],[#Data],[Qty]])",
        "=ROWS(Parts[[#Data],[#Totals],[Qty]])",
        "=INDEX(Parts[#All],MATCH(\"c\",Parts[[#All],[Part No]],0),3)",
        "=INDEX(Parts[Unit Price],MATCH(\"b\",Parts[Part No],0))",
        "=VLOOKUP(\"d\",Parts,2,FALSE)",
        "=SUM(Parts[Col'#])",
        "=SUM(Parts['[x']])",
        "=SUM(Parts[[Qty]:[Unit Price]])",
        "=SUMPRODUCT(Parts[Qty],Parts[Unit Price])",
        "=SUM(Parts[Line Total])",
        "=Parts[[#Totals],[Line Total]]",
        "=COLUMN(Parts[Unit Price])",
        "=ROW(Parts[#Headers])",
        "=ROW(Parts[#Totals])",
        "=MATCH(\"Qty\",Parts[#Headers],0)",
        "=COUNTIF(Parts[Qty],\">2\")",
        "=SUMIFS(Parts[Qty],Parts[Part No],\"<>a\")",
        "=AVERAGE(Parts[[#Data],[Qty]:[Unit Price]])",
        "=MAX(Parts[#Data])",
        "=Parts[[#Headers],[Col'#]]",
        "=Parts[[#Headers],['[x']]]",
    ]
    for i, fo in enumerate(forms, start=1):
        f.cell(row=i, column=1, value=fo[1:] if False else fo)
        f.cell(row=i, column=2, value=fo[1:])
    # this row from a formula beside the table on the Use sheet: implicit intersection of a column
    f["D2"] = "=Parts[Qty]*10"
    f["D3"] = "=Parts[Qty]*10"
    save(wb, "tables")


# ---------------------------------------------------------------- 3D references
# LibreOffice reads no 3D reference of Excel's spelling with a quoted sheet (`'Jan 1:Mar''s'!B2`
# is #NAME? there), so its oracle is three_d.fods: the same sheets and cells, each formula in
# ODF's spelling, which make.sh converts to three_d.lo.xlsx.
THREE_D = [
    ("SUM('Jan 1:Mar''s'!B2)", "SUM([$'Jan 1'.B2:$'Mar''s'.B2])"),
    ("SUM('Mar''s:Jan 1'!B2)", "SUM([$'Jan 1'.B2:$'Mar''s'.B2])"),
    ("SUM(Feb:'Apr-x'!A1:B3)", "SUM([$Feb.A1:$'Apr-x'.B3])"),
    ("SUM('Apr-x:Feb'!A1:B3)", "SUM([$Feb.A1:$'Apr-x'.B3])"),
    ("COUNT('Jan 1:Apr-x'!A1:C3)", "COUNT([$'Jan 1'.A1:$'Apr-x'.C3])"),
    ("COUNTA('Jan 1:Apr-x'!C1)", "COUNTA([$'Jan 1'.C1:$'Apr-x'.C1])"),
    ("AVERAGE('Jan 1:Feb'!A1)", "AVERAGE([$'Jan 1'.A1:$Feb.A1])"),
    ("MAX('Jan 1:Apr-x'!A1:B3)", "MAX([$'Jan 1'.A1:$'Apr-x'.B3])"),
    ("MIN('Jan 1:Apr-x'!A1:B3)", "MIN([$'Jan 1'.A1:$'Apr-x'.B3])"),
    ("SUM('Feb:Feb'!A1)", "SUM([$Feb.A1])"),
    ("SUM('Jan 1:Mar''s'!B2,1)", "SUM([$'Jan 1'.B2:$'Mar''s'.B2];1)"),
    ("PRODUCT('Jan 1:Feb'!A1)", "PRODUCT([$'Jan 1'.A1:$Feb.A1])"),
    ("SUMSQ('Jan 1:Feb'!A1)", "SUMSQ([$'Jan 1'.A1:$Feb.A1])"),
    ("COUNTBLANK(Feb!D1:D2)", "COUNTBLANK([$Feb.D1:.D2])"),
    ("STDEV('Jan 1:Apr-x'!A1)", "STDEV([$'Jan 1'.A1:$'Apr-x'.A1])"),
    ("'Jan 1'!A1+Feb!A1", "[$'Jan 1'.A1]+[$Feb.A1]"),
]
THREE_D_SHEETS = ["Jan 1", "Feb", "Mar's", "Apr-x"]


def three_d_value(k, r, c):
    return (k + 1) * 10 + r * c


def three_d():
    wb = Workbook()
    s = wb.active
    s.title = "Summary"
    for k, n in enumerate(THREE_D_SHEETS):
        ws = wb.create_sheet(n)
        for r in range(1, 4):
            for c in range(1, 3):
                ws.cell(row=r, column=c, value=three_d_value(k, r, c))
        ws["C1"] = "text"
    for i, (fo, _) in enumerate(THREE_D, start=1):
        s.cell(row=i, column=1, value="=" + fo)
    save(wb, "three_d")
    from xml.sax.saxutils import escape, quoteattr

    def cell(v):
        if isinstance(v, str) and v.startswith("of:"):
            return f"<table:table-cell table:formula={quoteattr(v)}/>"
        if isinstance(v, str):
            return f'<table:table-cell office:value-type="string"><text:p>{escape(v)}</text:p></table:table-cell>'
        return f'<table:table-cell office:value-type="float" office:value="{v}"/>'

    def table(name, rows):
        body = "".join("<table:table-row>" + "".join(cell(v) for v in r) + "</table:table-row>" for r in rows)
        return f"<table:table table:name={quoteattr(name)}>{body}</table:table>"

    tables = [table("Summary", [["of:=" + odf] for _, odf in THREE_D])]
    for k, n in enumerate(THREE_D_SHEETS):
        rows = [[three_d_value(k, r, c) for c in (1, 2)] + (["text"] if r == 1 else []) for r in (1, 2, 3)]
        tables.append(table(n, rows))
    ns = ('xmlns:office="urn:oasis:names:tc:opendocument:xmlns:office:1.0" '
          'xmlns:table="urn:oasis:names:tc:opendocument:xmlns:table:1.0" '
          'xmlns:text="urn:oasis:names:tc:opendocument:xmlns:text:1.0" '
          'xmlns:of="urn:oasis:names:tc:opendocument:xmlns:of:1.2"')
    with open(f"{out}/three_d.fods", "w") as f:
        f.write(f'<?xml version="1.0" encoding="UTF-8"?>\n<office:document {ns} office:version="1.2" '
                f'office:mimetype="application/vnd.oasis.opendocument.spreadsheet"><office:body>'
                f'<office:spreadsheet>{"".join(tables)}</office:spreadsheet></office:body></office:document>\n')


# ---------------------------------------------------------------- legacy CSE arrays
def cse():
    wb = Workbook()
    s = wb.active
    s.title = "Arr"
    for r in range(1, 5):
        s.cell(row=r, column=1, value=r)
        s.cell(row=r, column=2, value=r * 10)
        s.cell(row=r, column=3, value=r * 0.5)
    s["E1"] = ArrayFormula("E1:E4", "=A1:A4*B1:B4")
    s["F1"] = ArrayFormula("F1:F6", "=A1:A4+1")  # bigger than the source: #N/A
    s["G1"] = ArrayFormula("G1:G2", "=A1:A4*2")  # smaller
    s["H1"] = ArrayFormula("H1:I4", "=A1:B4*C1:C4")
    s["J1"] = ArrayFormula("J1:L3", "=A1:C1*2")  # a row replicated down
    s["M1"] = ArrayFormula("M1:N2", "=5")  # a scalar fills
    s["O1"] = ArrayFormula("O1", "=SUM(A1:A4*B1:B4)")
    s["P1"] = ArrayFormula("P1", "=A1:A4*3")  # one cell: top-left
    s["Q1"] = ArrayFormula("Q1", "=MAX(IF(A1:A4>2,B1:B4))")
    s["R1"] = ArrayFormula("R1:R3", "=TRANSPOSE(A1:C1)")
    s["S1"] = ArrayFormula("S1:T1", "=A2:A3")  # column into a row: replicated?
    s["U1"] = ArrayFormula("U1:U4", "=ROW(A1:A4)")
    s["V1"] = ArrayFormula("V1:V2", "=SUM(IF(A1:A4>1,1,0))")
    s["W1"] = ArrayFormula("W1", "=INDEX(A1:A4*B1:B4,3)")
    s["X1"] = ArrayFormula("X1:X3", "=MMULT(A1:C3,{1;1;1})")
    s["Y1"] = ArrayFormula("Y1:Z2", "={1,2;3,4}*A1")
    s["AA1"] = ArrayFormula("AA1:AA4", "=IF(A1:A4>2,\"big\",\"small\")")
    s["AB1"] = "=SUM(E1:E4)"
    s["AB2"] = "=SUM(H1:I4)"
    s["AB3"] = "=COUNTIF(F1:F6,\"#N/A\")"
    s["AB4"] = "=ISNA(F5)"
    save(wb, "cse")


# ---------------------------------------------------------------- 1904 dates
def d1904():
    wb = Workbook()
    wb.epoch = __import__("openpyxl").utils.datetime.CALENDAR_MAC_1904
    s = wb.active
    s.title = "D"
    s["A1"] = 0
    s["A2"] = 43000
    s["A3"] = 1.75
    forms = [
        '=TEXT(A1,"yyyy-mm-dd")',
        '=TEXT(A2,"dddd d mmmm yyyy")',
        '=TEXT(A3,"[h]:mm:ss")',
        '=TEXT(A2,"ddd")',
        "=DATE(2024,3,1)",
        "=DATE(1904,1,1)",
        "=DATE(1903,12,31)",
        "=YEAR(A1)",
        "=MONTH(A2)",
        "=DAY(A2)",
        "=WEEKDAY(A1)",
        "=WEEKDAY(A2,2)",
        '=DATEDIF(DATE(2020,1,31),DATE(2024,2,29),"md")',
        '=DATEDIF(DATE(2020,1,31),DATE(2024,2,29),"ym")',
        '=DATEDIF(A1,A2,"d")',
        '=DATEDIF(A1,A2,"y")',
        "=NETWORKDAYS(DATE(2024,1,1),DATE(2024,1,31))",
        "=NETWORKDAYS(A1,A1+30)",
        "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),11)",
        "=WORKDAY(DATE(2024,1,5),5)",
        '=DATEVALUE("2024-03-01")',
        '=DATEVALUE("1904-01-02")',
        "=EDATE(A2,1)",
        "=EOMONTH(A2,0)",
        "=WEEKNUM(A2)",
        "=_xlfn.ISOWEEKNUM(A2)",
        "=YEARFRAC(A1,A2)",
        "=_xlfn.DAYS(A2,A1)",
        "=DAYS360(A1,A2)",
        '=TEXT(DATE(2024,2,29),"d/m/yy")',
        '=VALUE("1/2/2024")',
        "=TIME(25,0,0)",
        '=TEXT(-1,"yyyy-mm-dd")',
        "=YEAR(-1)",
    ]
    for i, fo in enumerate(forms, start=1):
        s.cell(row=i, column=3, value=fo)
        s.cell(row=i, column=4, value=fo[1:])
    save(wb, "dates1904")


# ---------------------------------------------------------------- defined names
def names():
    wb = Workbook()
    s = wb.active
    s.title = "One"
    t = wb.create_sheet("Two Sheet")
    s["A1"] = 10
    s["A2"] = 20
    t["A1"] = 1000
    t["A2"] = 2000
    wb.defined_names["Gasket?"] = DefinedName("Gasket?", attr_text="One!$A$1")
    wb.defined_names["a\\b"] = DefinedName("a\\b", attr_text="One!$A$2")
    wb.defined_names["x.y"] = DefinedName("x.y", attr_text="One!$A$1:$A$2")
    wb.defined_names["_under"] = DefinedName("_under", attr_text="3.5")
    wb.defined_names["Rate"] = DefinedName("Rate", attr_text="One!$A$1")
    wb.defined_names["Twice"] = DefinedName("Twice", attr_text="One!$A$1*2")
    wb.defined_names["Rel"] = DefinedName("Rel", attr_text="One!$A1")
    t.defined_names["Rate"] = DefinedName("Rate", attr_text="'Two Sheet'!$A$2")
    t.defined_names["Local"] = DefinedName("Local", attr_text="'Two Sheet'!$A$1")
    f1 = ["=Gasket?", "=a\\b", "=SUM(x.y)", "=_under*2", "=Rate", "=Twice", "=Rel", "='Two Sheet'!Local",
          "='Two Sheet'!Rate", "=Gasket?+a\\b"]
    for i, fo in enumerate(f1, start=1):
        s.cell(row=i, column=3, value=fo)
        s.cell(row=i, column=4, value=fo[1:])
    f2 = ["=Rate", "=Local", "=One!Rate+0", "=Gasket?", "=SUM(x.y)", "=Rate*2"]
    for i, fo in enumerate(f2, start=1):
        t.cell(row=i, column=3, value=fo)
        t.cell(row=i, column=4, value=fo[1:])
    save(wb, "names")


# ---------------------------------------------------------------- iteration
def iteration(name, count, delta):
    wb = Workbook()
    wb.calculation.iterate = True
    wb.calculation.iterateCount = count
    wb.calculation.iterateDelta = delta
    s = wb.active
    s.title = "It"
    s["A1"] = "=(A1+2/A1)/2"  # starts at 0: #DIV/0! in Excel too
    s["B1"] = 5
    s["B2"] = "=B2/2+B1"  # converges to 10
    s["C1"] = "=C1+1"  # never converges: count iterations
    s["D1"] = "=D2+1"
    s["D2"] = "=D1/2"  # converges to D1=2, D2=1
    s["E1"] = "=0.5*E1+1"  # converges to 2
    save(wb, name)


# ---------------------------------------------------------------- TEXT formats
def text_formats():
    wb = Workbook()
    s = wb.active
    s.title = "T"
    values = [0, 1.25, -1.25, 0.3333333333, 1234567.891, -0.5, 3.14159, 12, 0.03125, 100000000, 45292.75, "abc"]
    fmts = [
        "# ??/??", "# #/##", "?/?", "# ?/8", "0 ??/16", "#,##0.00", "0,,", "0.0,,\"M\"", "#,##0,", "[h]:mm:ss",
        "[<1]0.00;#,##0", "[Red]0.0;[Blue]-0.0", "[$-409]d-mmm-yy", "@", "0.00_);(0.00)", "0*-", "**0.0",
        "0.0E+00", "##0.0E+0", ".#", "0.000\" mm\"", "#.##", "0%", "0.0%", "\"x\"0;\"y\"0;\"zero\"", "[>=100]\"big\";[<0]\"neg\";0.0",
        "$#,##0.00", "0 \"deg\"", "[mm]:ss", "mm:ss.00", "General", "0.###", "000-000", "\\A0",
        "#,###", "0.00;-0.00;\"-\"", "# ?/?", "[$€-407] #,##0.00", "yyyy-mm-dd hh:mm", "d \"days\"",
    ]
    for c, v in enumerate(values, start=2):
        s.cell(row=1, column=c, value=v)
    for r, fm in enumerate(fmts, start=2):
        s.cell(row=r, column=1, value=fm)
        for c in range(2, 2 + len(values)):
            col = s.cell(row=1, column=c).column_letter
            s.cell(row=r, column=c, value=f"=TEXT({col}$1,$A{r})")
    save(wb, "text_formats")


# ---------------------------------------------------------------- which error wins
def errors():
    wb = Workbook()
    s = wb.active
    s.title = "E"
    forms = [
        "=1/0+NA()", "=NA()+1/0", "=SUM(1/0,NA())", "=SUM(NA(),1/0)", "=IF(NA(),1/0)", "=ROUND(1/0,NA())",
        "=ROUND(NA(),1/0)", "=MID(NA(),1/0,1)", "=DATE(1/0,NA(),1)", "=VLOOKUP(NA(),1/0,1)", "=MAX(1/0,NA())",
        "=AND(NA(),1/0)", "=AND(\"1\",1)", "=AND(\"x\",NA())", "=LARGE({1,2},NA())", "=LARGE(NA(),1/0)",
        "=YEARFRAC(1/0,200,-1)", "=YEARFRAC(1,200,-1)", "=YEARFRAC(\"x\",NA())", "=INDEX({1,2},NA())",
        "=MATCH(NA(),{1,2},0)", "=CONCATENATE(1/0,NA())", "=\"a\"&NA()&1/0", "=-NA()", "=(1/0)^NA()",
        "=SQRT(-1)+NA()", "=NA()+SQRT(-1)", "=LOG(-1,NA())", "=POWER(0,-1)", "=POWER(-8,1/3)",
        "=MOD(5,0)", "=MOD(NA(),0)", "=IFERROR(1/0,NA())", "=ISERROR(NA())+1/0", "=SUMPRODUCT({1,2},{1,2,3})",
        "=SUMPRODUCT({1,#N/A},{1/0,1})", "=CHOOSE(0,1,2)", "=CHOOSE(NA(),1/0)", "=CHOOSE(3,1,2)",
        "=TEXT(NA(),1/0)", "=REPT(\"a\",-1)", "=LEFT(\"abc\",-1)", "=FIND(\"z\",\"abc\")", "=FACT(-1)",
        "=COMBIN(2,3)", "=SUM({1,#DIV/0!,#N/A})", "=MIN(NA(),\"x\"+1)", "=ABS(\"x\")", "=\"x\"+NA()",
        "=NA()+\"x\"", "=1/0&\"x\"", "=DATEDIF(2,1,\"d\")", "=DATEDIF(1,2,\"q\")", "=NETWORKDAYS(1/0,NA())",
        "=EDATE(NA(),1/0)", "=FLOOR(5,-1)", "=CEILING(-5,2)", "=CEILING(5,-2)", "=MROUND(5,-2)",
    ]
    for i, fo in enumerate(forms, start=1):
        s.cell(row=i, column=1, value=fo)
        s.cell(row=i, column=2, value=fo[1:])
    save(wb, "errors")


# ---------------------------------------------------------------- engineering design table
def engineering():
    wb = Workbook()
    s = wb.active
    s.title = "Design"
    lk = wb.create_sheet("Threads")
    lk.append(["Size", "Pitch", "Minor", "Name"])
    for row in [(3, 0.5, 2.459, "M3"), (4, 0.7, 3.242, "M4"), (5, 0.8, 4.134, "M5"), (6, 1.0, 4.917, "M6"),
                (8, 1.25, 6.647, "M8"), (10, 1.5, 8.376, "M10"), (12, 1.75, 10.106, "M12"), (16, 2, 13.835, "M16")]:
        lk.append(list(row))
    lk["F1"] = "Name"
    for i, n in enumerate(["alpha", "beta", "Gamma", "delta", "epsilon"], start=2):
        lk.cell(row=i, column=6, value=n)
    # horizontal table
    lk["H1"], lk["I1"], lk["J1"], lk["K1"] = "Mat", 0, 100, 250
    lk["H2"], lk["I2"], lk["J2"], lk["K2"] = "Speed", 300, 220, 150
    vals = [2.5, -2.5, 1.005, -1.005, 2.345, -2.345, 0.5, -0.5, 1e-16, -7.25, 123.456789, 1.15]
    forms = [
        "=ROUND({v},2)", "=ROUND({v},0)", "=ROUND({v},-1)", "=ROUNDUP({v},1)", "=ROUNDDOWN({v},1)",
        "=MROUND({v},0.05)", "=MROUND({v},-0.05)", "=CEILING({v},0.1)", "=CEILING({v},-0.1)", "=FLOOR({v},0.1)",
        "=FLOOR({v},-0.1)", "=_xlfn.CEILING.MATH({v},0.5)", "=_xlfn.CEILING.MATH({v},0.5,1)", "=_xlfn.FLOOR.MATH({v},0.5,1)",
        "=INT({v})", "=TRUNC({v},1)", "=EVEN({v})", "=ODD({v})", "=MOD({v},0.3)", "=MOD({v},-0.7)",
        "=TEXT({v},\"0.000\"\" mm\"\"\")", "=TEXT({v},\"#,##0.0##\")", "=FIXED({v},3)", "={v}*3-{v}*2",
        "=SQRT(ABS({v}))", "=DEGREES(ATAN2(1,{v}))", "=TEXT({v}/3,\"0.00E+00\")", "={v}/3&\" mm\"",
    ]
    r = 1
    for fo in forms:
        for c, v in enumerate(vals, start=1):
            s.cell(row=r, column=c, value=fo.format(v=repr(v)))
        r += 1
    extra = [
        "=DEGREES(ASIN(1))", "=DEGREES(ASIN(-1))", "=ASIN(1.0000000000000002)", "=DEGREES(ACOS(0.99999999999999))",
        "=DEGREES(ATAN2(-1,-0))", "=DEGREES(ATAN2(-1,0))", "=ATAN2(0,0)", "=RADIANS(180)", "=DEGREES(PI())",
        "=SQRT(0.1+0.2-0.3)", "=SQRT(0.3-0.2-0.1)", "=SQRT(-1E-17)", "=0.1+0.2-0.3", "=1-0.9-0.1", "=3*1.1-3.3",
        "=VLOOKUP(7,Threads!A2:D9,2)", "=VLOOKUP(7,Threads!A2:D9,2,TRUE)", "=VLOOKUP(2,Threads!A2:D9,2)",
        "=VLOOKUP(100,Threads!A2:D9,4)", "=VLOOKUP(\"M8\",Threads!D2:D9,1,FALSE)", "=VLOOKUP(\"m*\",Threads!D2:D9,1,FALSE)",
        "=VLOOKUP(\"c\",Threads!F2:F6,1)", "=VLOOKUP(\"zz\",Threads!F2:F6,1)", "=VLOOKUP(\"Beta\",Threads!F2:F6,1)",
        "=HLOOKUP(120,Threads!I1:K2,2)", "=HLOOKUP(-1,Threads!I1:K2,2)", "=HLOOKUP(250,Threads!I1:K2,2,FALSE)",
        "=INDEX(Threads!B2:B9,MATCH(\"M1?\",Threads!D2:D9,0))", "=MATCH(\"*ta\",Threads!F2:F6,0)",
        "=MATCH(\"g*\",Threads!F2:F6,0)", "=MATCH(\"~*\",Threads!F2:F6,0)", "=MATCH(9,Threads!A2:A9)", "=MATCH(9,Threads!A2:A9,1)",
        "=MATCH(9,Threads!A9:A2,-1)", "=IFERROR(VLOOKUP(7,Threads!A2:D9,2,FALSE),IFERROR(VLOOKUP(8,Threads!A2:D9,2,FALSE),0))",
        "=CHOOSE(2,\"a\",\"b\",\"c\")", "=CHOOSE(2.9,10,20,30)", "=CHOOSE({1,2},10,20)",
        "=TEXT(DATE(2024,3,5),\"dd.mm.yyyy\")", "=TEXT(45292.5,\"yyyy-mm-dd hh:mm\")", "=DATE(2024,13,1)", "=DATE(2024,1,0)",
        "=1/3", "=2/3*3", "=10/3", "=1E15+0.3", "=123456789012345678", "=0.1*3", "=1234567.89012345",
        "=TEXT(1/3,\"General\")", "=1/3&\"\"", "=12345678901234567&\"\"", "=0.000012345&\"\"", "=1E-20&\"\"",
        "=VALUE(\"1.5E3\")", "=\"3\"*\"4\"", "=TEXT(2.675,\"0.00\")", "=ROUND(2.675,2)", "=ROUND(1.0049999999999999,2)",
        "=PI()*25^2/4", "=TAN(RADIANS(45))", "=SIN(RADIANS(30))", "=COS(RADIANS(60))", "=TAN(RADIANS(90))",
        "=ATAN(1)*4", "=SQRT(2)^2", "=SQRT(2)^2=2", "=0.1+0.2=0.3", "=ROUNDUP(-2.1,0)", "=ROUNDDOWN(-2.9,0)",
        "=CEILING(-2.5,1)", "=FLOOR(-2.5,1)", "=CEILING(-2.5,-1)", "=FLOOR(-2.5,-1)", "=MROUND(-7.5,-5)",
    ]
    for i, fo in enumerate(extra, start=r + 1):
        s.cell(row=i, column=1, value=fo)
        s.cell(row=i, column=2, value=fo[1:])
    save(wb, "engineering")


tables()
three_d()
cse()
d1904()
names()
iteration("iterate_converge", 100, 0.001)
iteration("iterate_capped", 10, 0.000001)
text_formats()
errors()
engineering()
