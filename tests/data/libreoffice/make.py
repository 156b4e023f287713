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
          "errors", "engineering", "lookups", "rounding", "trig_criteria", "text_numbers", "schedule",
          "error_ranges", "design_more", "implicit", "compare_criteria", "spacing", "stats_edges", "date_formats"]
if out == "--list":
    print(" ".join(PROBES))
    sys.exit(0)
# `make.py DIR NAME...` writes only the probes named (the others keep their committed bytes).
ONLY = set(sys.argv[2:])


def save(wb, name):
    if ONLY and name not in ONLY:
        return
    wb.save(f"{out}/{name}.xlsx")


def book(*titles):
    """A workbook with sheets of these titles, in order, and the sheets."""
    wb = Workbook()
    sheets = [wb.active]
    sheets[0].title = titles[0]
    sheets += [wb.create_sheet(t) for t in titles[1:]]
    return wb, sheets


def text_table(s, values, fmts):
    """Values across row 1, formats down column A, and TEXT of each value in each format."""
    for c, v in enumerate(values, start=2):
        s.cell(row=1, column=c, value=v)
    for r, fm in enumerate(fmts, start=2):
        s.cell(row=r, column=1, value=fm)
        for c in range(2, 2 + len(values)):
            col = s.cell(row=1, column=c).column_letter
            s.cell(row=r, column=c, value=f"=TEXT({col}$1,$A{r})")


# ---------------------------------------------------------------- tables
def tables():
    wb, (d,) = book("Parts Data")
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
    listed(f, forms)
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
    wb, (s,) = book("Summary")
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
    wb, (s,) = book("Arr")
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
    listed(s, forms, col=3)
    save(wb, "dates1904")


# ---------------------------------------------------------------- defined names
def names():
    wb, (s, t) = book("One", "Two Sheet")
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
    listed(s, f1, col=3)
    f2 = ["=Rate", "=Local", "=One!Rate+0", "=Gasket?", "=SUM(x.y)", "=Rate*2"]
    listed(t, f2, col=3)
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
    wb, (s,) = book("T")
    values = [0, 1.25, -1.25, 0.3333333333, 1234567.891, -0.5, 3.14159, 12, 0.03125, 100000000, 45292.75, "abc"]
    fmts = [
        "# ??/??", "# #/##", "?/?", "# ?/8", "0 ??/16", "#,##0.00", "0,,", "0.0,,\"M\"", "#,##0,", "[h]:mm:ss",
        "[<1]0.00;#,##0", "[Red]0.0;[Blue]-0.0", "[$-409]d-mmm-yy", "@", "0.00_);(0.00)", "0*-", "**0.0",
        "0.0E+00", "##0.0E+0", ".#", "0.000\" mm\"", "#.##", "0%", "0.0%", "\"x\"0;\"y\"0;\"zero\"", "[>=100]\"big\";[<0]\"neg\";0.0",
        "$#,##0.00", "0 \"deg\"", "[mm]:ss", "mm:ss.00", "General", "0.###", "000-000", "\\A0",
        "#,###", "0.00;-0.00;\"-\"", "# ?/?", "[$€-407] #,##0.00", "yyyy-mm-dd hh:mm", "d \"days\"",
    ]
    text_table(s, values, fmts)
    save(wb, "text_formats")


# ---------------------------------------------------------------- which error wins
def errors():
    wb, (s,) = book("E")
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
    listed(s, forms)
    save(wb, "errors")


# ---------------------------------------------------------------- engineering design table
def engineering():
    wb, (s, lk) = book("Design", "Threads")
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
    listed(s, extra, start=r + 1)
    save(wb, "engineering")


# ---------------------------------------------------------------- second round: design-table forms
def listed(ws, forms, col=1, start=1):
    """Each formula in column `col` from row `start` on, its text beside it (the test names a
    cell by its row)."""
    for i, fo in enumerate(forms, start=start):
        if isinstance(fo, tuple):  # a one-cell legacy array formula
            at = ws.cell(row=i, column=col).coordinate
            ws.cell(row=i, column=col, value=ArrayFormula(at, fo[1]))
            ws.cell(row=i, column=col + 1, value="{" + fo[1] + "}")
        else:
            ws.cell(row=i, column=col, value=fo)
            ws.cell(row=i, column=col + 1, value=fo[1:])


def cse1(fo):
    return ("cse", fo)


def lookups():
    wb, (s, t) = book("L", "T")
    for i, (a, b) in enumerate(zip([1, 2, 3, 5, 8, 13, 21, 34], ["one", "two", "three", "five", "eight", "thirteen",
                                                                  "twenty-one", "thirty-four"]), start=1):
        t.cell(row=i, column=1, value=a)
        t.cell(row=i, column=2, value=b)
    for i, v in enumerate([5, 3, 9, 1, 7, 3], start=1):
        t.cell(row=i, column=3, value=v)
    for i, v in enumerate([1, "2", 3, "abc", True, 4.5], start=1):
        t.cell(row=i, column=4, value=v)
    for i, v in enumerate(["apple", "Banana", "cherry", "date", "Elder"], start=1):
        t.cell(row=i, column=5, value=v)
    for i, v in enumerate(["ABC", "abc", "Abc", "a*c", "a?c"], start=1):
        t.cell(row=i, column=6, value=v)
    for c, (a, b) in enumerate(zip([0, 10, 20, 30, 40], ["a", "b", "c", "d", "e"]), start=8):
        t.cell(row=10, column=c, value=a)
        t.cell(row=11, column=c, value=b)
    for i, v in enumerate([0.1, 0.2, 0.30000000000000004, 0.4], start=1):
        t.cell(row=i, column=7, value=v)
    forms = [
        "=VLOOKUP(4,T!A1:B8,2)", "=VLOOKUP(0,T!A1:B8,2)", "=VLOOKUP(34,T!A1:B8,2)", "=VLOOKUP(100,T!A1:B8,2)",
        "=VLOOKUP(5,T!A1:B8,2,FALSE)", "=VLOOKUP(4,T!A1:B8,2,0)", "=VLOOKUP(\"5\",T!A1:B8,2,FALSE)",
        "=VLOOKUP(3,T!C1:C6,1,FALSE)", "=VLOOKUP(4,T!A1:B8,0)", "=VLOOKUP(4,T!A1:B8,3)", "=VLOOKUP(4.9999,T!A1:B8,2)",
        "=VLOOKUP(4,T!E1:E5,1)", "=VLOOKUP(\"c\",T!E1:E5,1)", "=VLOOKUP(\"BANANA\",T!E1:E5,1,FALSE)",
        "=VLOOKUP(\"b*\",T!E1:E5,1,FALSE)", "=VLOOKUP(\"?a*\",T!E1:E5,1,FALSE)", "=VLOOKUP(\"a~*c\",T!F1:F5,1,FALSE)",
        "=MATCH(3,T!C1:C6,0)", "=MATCH(7,T!C1:C6,0)", "=MATCH(\"abc\",T!F1:F5,0)", "=MATCH(\"a~*c\",T!F1:F5,0)",
        "=MATCH(\"a~?c\",T!F1:F5,0)", "=MATCH(\"a?c\",T!F1:F5,0)", "=MATCH(\"B*\",T!E1:E5,0)", "=MATCH(\"c\",T!E1:E5)",
        "=MATCH(\"zzz\",T!E1:E5)", "=MATCH(\"a\",T!E1:E5)", "=MATCH(2,T!D1:D6,0)", "=MATCH(\"2\",T!D1:D6,0)",
        "=MATCH(TRUE,T!D1:D6,0)", "=MATCH(4.5,T!D1:D6,0)", "=MATCH(4,{8,5,3,1},-1)", "=MATCH(9,{8,5,3,1},-1)",
        "=MATCH(0,{8,5,3,1},-1)", "=MATCH(0.3,T!G1:G4,0)", "=MATCH(0.3,T!G1:G4)", "=MATCH(\"\",T!E1:E5,0)",
        "=HLOOKUP(25,T!H10:L11,2)", "=HLOOKUP(40,T!H10:L11,2)", "=HLOOKUP(-1,T!H10:L11,2)", "=HLOOKUP(20,T!H10:L11,3)",
        "=HLOOKUP(20,T!H10:L11,2,FALSE)", "=HLOOKUP(\"*\",T!H11:L11,1,FALSE)",
        "=SUM(INDEX(T!A1:B8,0,1))", "=ROWS(INDEX(T!A1:B8,0,2))", "=COLUMNS(INDEX(T!A1:B8,3,0))", "=INDEX(T!A1:A8,4)",
        "=INDEX(T!A1:B8,4,2)", "=INDEX(T!H10:L10,3)", "=INDEX(T!A1:B8,9,1)", "=INDEX({1,2;3,4},2,2)", "=INDEX({1,2,3},2)",
        "=SUM(INDEX(T!A1:B8,0,0))", "=INDEX(T!A1:B8,2.9,1.9)", "=INDEX(T!A1:A8,-1)",
        "=LOOKUP(4,T!A1:A8,T!B1:B8)", "=LOOKUP(4,T!A1:B8)", "=LOOKUP(25,T!H10:L11)", "=LOOKUP(\"c\",T!E1:E5)",
        "=LOOKUP(2,{1,2,3},{\"a\",\"b\",\"c\"})", "=LOOKUP(0,T!A1:A8,T!B1:B8)", "=LOOKUP(100,T!A1:A8,T!B1:B8)",
        "=LOOKUP(2.5,{1,2,3;10,20,30})", "=LOOKUP(15,T!H10:L10,T!H11:L11)", "=LOOKUP(\"zz\",T!E1:E5,T!A1:A5)",
        "=_xlfn.XLOOKUP(5,T!A1:A8,T!B1:B8)", "=_xlfn.XLOOKUP(4,T!A1:A8,T!B1:B8,\"none\")",
        "=_xlfn.XLOOKUP(4,T!A1:A8,T!B1:B8,,-1)", "=_xlfn.XLOOKUP(4,T!A1:A8,T!B1:B8,,1)",
        "=_xlfn.XLOOKUP(\"c*\",T!E1:E5,T!A1:A5,,2)", "=_xlfn.XLOOKUP(3,T!C1:C6,T!D1:D6,,0,-1)",
        "=_xlfn.XLOOKUP(\"ABC\",T!F1:F5,T!A1:A5)", "=_xlfn.XMATCH(8,T!A1:A8)", "=_xlfn.XMATCH(9,T!A1:A8,1)",
        "=_xlfn.XMATCH(9,T!A1:A8,-1)", "=_xlfn.XMATCH(21,T!A1:A8,0,2)", "=_xlfn.XLOOKUP(4,T!A1:A8,T!B1:B8)",
        "=VLOOKUP(TRUE,T!D1:D6,1,FALSE)", "=VLOOKUP(2,T!D1:D6,1)", "=MATCH(4,T!D1:D6)", "=MATCH(\"b\",T!D1:D6)",
        "=COUNTIF(T!F1:F5,\"abc\")", "=COUNTIF(T!F1:F5,\"a~*c\")", "=COUNTIF(T!F1:F5,\"a*\")", "=SUMPRODUCT(--EXACT(T!F1:F5,\"abc\"))",
        "=VLOOKUP(8,T!A1:B8,2,TRUE)&\"/\"&VLOOKUP(9,T!A1:B8,2,TRUE)", "=INDEX(T!B1:B8,MATCH(MAX(T!A1:A8),T!A1:A8,0))",
        "=SUMPRODUCT(VLOOKUP(5,T!A1:C8,{1,3},FALSE))", "=SUMPRODUCT(VLOOKUP({3,5},T!A1:B8,1,FALSE))",
        "=SUMPRODUCT(HLOOKUP({10,30},T!H10:L11,1,FALSE))", "=SUMPRODUCT(--(VLOOKUP(T!A1:A3,T!A1:B8,2,FALSE)=\"two\"))",
    ]
    listed(s, forms)
    save(wb, "lookups")


ROUND_VALUES = [2.5, -2.5, 0.5, -0.5, 1.5, -1.5, 2.675, -2.675, 5.1, -5.1, 7, -7, 0, 0.1, 1e15 + 0.5, 123456.785,
                4.35, -0.05]


def rounding():
    wb, (s,) = book("R")
    forms = [
        "=ROUND({v},2)", "=ROUND({v},0)", "=ROUND({v},-1)", "=ROUNDUP({v},0)", "=ROUNDDOWN({v},0)", "=ROUNDUP({v},-1)",
        "=MROUND({v},3)", "=MOD({v},3)", "=MOD({v},-3)", "=MOD({v},1)", "=MOD({v},0.1)", "=MOD({v},2.5)",
        "=QUOTIENT({v},3)", "=QUOTIENT({v},-3)", "=QUOTIENT({v},0.5)", "=INT({v})", "=TRUNC({v})", "=TRUNC({v},-1)",
        "=EVEN({v})", "=ODD({v})", "=_xlfn.CEILING.MATH({v})", "=_xlfn.CEILING.MATH({v},2)", "=_xlfn.CEILING.MATH({v},-2)",
        "=_xlfn.CEILING.MATH({v},2,-1)", "=_xlfn.FLOOR.MATH({v})", "=_xlfn.FLOOR.MATH({v},-2,1)",
        "=_xlfn.FLOOR.MATH({v},2,0)", "=_xlfn.CEILING.PRECISE({v},-2)", "=_xlfn.FLOOR.PRECISE({v},2)",
        "=ISO.CEILING({v},2)", "=CEILING({v},1)", "=FLOOR({v},1)", "=CEILING({v},0.5)", "=FLOOR({v},0.5)",
        "=SIGN({v})", "=ROUND({v}*100,0)/100", "=ROUND({v},15)", "=ROUND({v},-16)", "=ROUNDUP({v},2)", "=ROUNDDOWN({v},2)",
        "=MROUND({v},0.1)", "=CEILING({v},0)", "=FLOOR({v},0)", "=MOD({v},0)", "=QUOTIENT({v},0)",
    ]
    for r, fo in enumerate(forms, start=1):
        for c, v in enumerate(ROUND_VALUES, start=1):
            s.cell(row=r, column=c, value=fo.format(v=repr(v)))
    x = wb.create_sheet("X")
    listed(x, [
        "=ROUND(2.675,2)", "=ROUND(1.005,2)", "=ROUND(-1.005,2)", "=ROUND(0.285,2)", "=ROUND(1.0049999999999999,2)",
        "=ROUND(8.345,2)", "=ROUND(1234.5675,3)", "=ROUND(0.1+0.2,15)", "=MOD(-1,3)", "=MOD(5.1,1)", "=MOD(-5.1,1)",
        "=MOD(1E10,3)", "=MOD(2^40,7)", "=MOD(10,0.2)", "=MOD(0.3,0.1)", "=MOD(-0.3,0.1)", "=QUOTIENT(-7,2)",
        "=QUOTIENT(7.9,2.1)", "=INT(-0.0000001)", "=TRUNC(-0.0000001)", "=EVEN(-0.1)", "=ODD(-0.1)", "=ODD(0)",
        "=EVEN(0)", "=ODD(2)", "=EVEN(-3)", "=GCD(12.7,18.2)", "=LCM(4.5,6)", "=GCD(-4,6)", "=FACT(4.9)", "=COMBIN(5.9,2.1)",
        "=ROUNDUP(3.0000000000000004,0)", "=ROUNDUP(0.1*3,1)", "=ROUNDDOWN(0.7*3,1)", "=CEILING(0.1*3,0.1)",
        "=FLOOR(0.7*3,0.1)", "=MROUND(0.1*3,0.1)", "=MROUND(1.3,0.2)", "=MROUND(-1.3,-0.2)", "=CEILING(4.35,0.05)",
        "=FLOOR(4.35,0.05)", "=INT(4.35/0.05)", "=TRUNC(4.35*100)", "=INT(0.29*100)", "=ROUND(-2.5,0)", "=ROUNDUP(-2.5,0)",
        "=ROUNDDOWN(-2.5,0)", "=_xlfn.CEILING.MATH(-2.5)", "=_xlfn.CEILING.MATH(-2.5,1,1)", "=_xlfn.FLOOR.MATH(-2.5)",
        "=_xlfn.FLOOR.MATH(-2.5,1,1)", "=CEILING(-2.5,-2)", "=FLOOR(-2.5,-2)", "=CEILING(2.5,0.3)", "=FLOOR(2.5,0.3)",
        "=MOD(-7,-3)", "=MOD(7,-3)", "=MOD(-7,3)", "=MOD(7.5,-2)", "=SIGN(-0)", "=ABS(-0)", "=1-1E-16=1",
        "=ROUND(45.3499999999999,1)", "=ROUND(1E300*10,0)", "=ROUND(5E-324,0)", "=ROUND(123,-3)", "=ROUND(-501,-3)",
        "=INT(1E20)", "=MOD(3,1E-300)", "=EVEN(1E300)", "=ROUND(2.5,)", "=ROUND(2.5)",
    ])
    save(wb, "rounding")


def trig_criteria():
    wb, (s, d) = book("G", "D")
    rows = [("2024-01-05", 10, "bolt M6", True, "3"), ("2024-01-15", 20, "nut M6", False, 4),
            ("2024-02-01", 30, "bolt M8", True, "x"), ("2024-02-20", 40, "washer", None, 5),
            ("2023-12-31", 50, "", 1, "1"), ("2024-03-01", 60, "Bolt m10", "yes", 1)]
    import datetime
    for i, (dt, q, name, b, t) in enumerate(rows, start=1):
        d.cell(row=i, column=1, value=datetime.date.fromisoformat(dt))
        d.cell(row=i, column=2, value=q)
        if name != "":
            d.cell(row=i, column=3, value=name)
        if b is not None:
            d.cell(row=i, column=4, value=b)
        d.cell(row=i, column=5, value=t)
    d["C5"] = '=""'  # empty text from a formula
    listed(s, [
        "=RADIANS(-90)", "=DEGREES(-PI()/2)", "=RADIANS(720)", "=DEGREES(ATAN2(1,2))", "=DEGREES(ATAN2(2,1))",
        "=DEGREES(ATAN2(-1,0))", "=DEGREES(ATAN2(0,-1))", "=DEGREES(ATAN2(-1,-1))", "=DEGREES(ATAN2(1,-0.0000001))",
        "=ASIN(1.1)", "=ACOS(-1.0000001)", "=ASIN(-1)", "=ACOS(-1)", "=DEGREES(ACOS(0.5))", "=ATAN(1E300)",
        "=SQRT(-4)", "=SQRT(0)", "=SQRT(\"4\")", "=POWER(0,0)", "=0^0", "=POWER(-8,1/3)", "=(-8)^(1/3)",
        "=POWER(-2,3)", "=POWER(-2,0.5)", "=POWER(2,-1)", "=POWER(-2,-2)", "=2^1024", "=-2^2", "=-2^0.5", "=2^-1",
        "=POWER(0,-1)", "=0^-0.5", "=POWER(-1,1E10)", "=POWER(4,0.5)", "=10^-400", "=(-0.5)^2.5",
        "=SIN(PI())", "=COS(PI()/2)", "=TAN(PI()/4)", "=SIN(PI()*1E10)", "=COS(2*PI())", "=SIN(RADIANS(180))",
        "=COS(RADIANS(90))", "=TAN(RADIANS(270))", "=SIN(1E20)", "=PI()*2", "=PI()/180*57.29577951308232",
        "=SUMSQ(1,\"2\",TRUE)", "=SUMSQ(D!D1:D6)", "=SUMSQ(D!E1:E6)", "=SUMSQ(D!B1:B3,-2)", "=SUMSQ({1,\"2\",TRUE})",
        "=SUMPRODUCT(D!D1:D6)", "=SUMPRODUCT(--D!D1:D6)", "=SUMPRODUCT(D!D1:D6*1)", "=SUMPRODUCT(D!E1:E6)",
        "=SUMPRODUCT(D!E1:E6,D!B1:B6)", "=SUMPRODUCT((D!B1:B6>25)*D!B1:B6)", "=SUMPRODUCT((D!B1:B6>25),D!B1:B6)",
        "=SUMPRODUCT(--(D!E1:E6>2))", "=SUMPRODUCT(D!B1:B6,D!B1:B6)", "=SUMPRODUCT(D!B1:B3*D!E1:E3)",
        "=SUMIFS(D!B1:B6,D!A1:A6,\">=\"&DATE(2024,1,1))", "=SUMIFS(D!B1:B6,D!A1:A6,\">=\"&DATE(2024,1,1),D!A1:A6,\"<\"&DATE(2024,2,1))",
        "=SUMIFS(D!B1:B6,D!A1:A6,\">=2024-02-01\")", "=SUMIFS(D!B1:B6,D!A1:A6,\">1/15/2024\")", "=COUNTIFS(D!C1:C6,\"<>\")",
        "=COUNTIFS(D!C1:C6,\"\")", "=COUNTIFS(D!C1:C6,\"=\")", "=COUNTIF(D!C1:C6,\"<>bolt*\")", "=COUNTIF(D!C1:C6,\"bolt*\")",
        "=COUNTIF(D!C1:C6,\"*m?\")", "=COUNTIF(D!C1:C6,\"*M6\")", "=COUNTIF(D!E1:E6,\"1\")", "=COUNTIF(D!E1:E6,1)",
        "=COUNTIF(D!E1:E6,\">2\")", "=COUNTIF(D!E1:E6,\"3\")", "=COUNTIF(D!D1:D6,TRUE)", "=COUNTIF(D!D1:D6,\"TRUE\")",
        "=COUNTIF(D!D1:D6,1)", "=COUNTIF(D!B1:B6,\">=\"&\"30\")", "=COUNTIF(D!B1:B6,\"<>20\")", "=COUNTIF(D!B1:B6,\">2E1\")",
        "=AVERAGEIFS(D!B1:B6,D!C1:C6,\"bolt*\")", "=AVERAGEIFS(D!B1:B6,D!C1:C6,\"nothing\")",
        "=AVERAGEIFS(D!B1:B6,D!A1:A6,\"<\"&DATE(2024,2,1),D!C1:C6,\"<>\")", "=AVERAGEIF(D!B1:B6,\">25\")",
        "=SUMIF(D!C1:C6,\"<>\",D!B1:B6)", "=SUMIF(D!C1:C6,\"\",D!B1:B6)", "=SUMIF(D!E1:E6,\"<>x\",D!B1:B6)",
        "=SUMIF(D!C1:C6,\"*~?*\",D!B1:B6)", "=SUMIF(D!B1:B6,\">\"&25)", "=SUMIF(D!B1:B6,\"25<\")", "=SUMIF(D!B1:B6,\"=\"&\"\")",
        "=COUNTIFS(D!A1:A6,\">=\"&DATE(2024,1,1),D!B1:B6,\"<=40\")", "=COUNTIF(D!A1:A6,DATE(2024,1,15))",
        "=COUNTIF(D!A1:A6,\"1/15/2024\")", "=SUMIF(D!A1:A6,\"<=\"&D!A2,D!B1:B6)", "=SUMIFS(D!B1:B6,D!C1:C6,\"BOLT*\")",
    ])
    save(wb, "trig_criteria")


def text_numbers():
    wb, (s, d) = book("N", "D")
    for i, v in enumerate(["3", 4, True, " 5 ", None, "abc", 1.5], start=1):
        if v is not None:
            d.cell(row=i, column=1, value=v)
    listed(s, [
        "=1/3&\"\"", "=1E+20&\"\"", "=1E21&\"\"", "=-0&\"\"", "=0.1+0.2&\"\"", "=123456789012345&\"\"",
        "=1234567890123456&\"\"", "=1E-5&\"\"", "=0.0001&\"\"", "=-1.5E-10&\"\"", "=2^53&\"\"", "=1E100&\"\"",
        "=TRUE&\"\"", "=100000000000000000000&\"\"", "=123456789012345.6&\"\"", "=0.1234567890123456&\"\"",
        "=99999999999999.99&\"\"", "=999999999999999.9&\"\"", "=1.23456789012345E-7&\"\"", "=-1/3&\" mm\"",
        "=25.4*3&\"\"", "=2/3*3&\"\"", "=\"Ø\"&10&\" H7\"", "=\"R\"&0.5*3", "=12.5&\"x\"&45&\"°\"",
        "=TEXT(12.3456,\"0.000\")", "=TEXT(-12.3456,\"0.000\")", "=TEXT(1234567.891,\"#,##0.00\")", "=TEXT(-0.004,\"#,##0.00\")",
        "=TEXT(0.000123,\"0.00E+00\")", "=TEXT(-123456,\"0.00E+00\")", "=TEXT(45,\"0°\")", "=TEXT(12.25,\"0.0\"\" mm\"\"\")",
        "=TEXT(2.5,\"0\")", "=TEXT(-2.5,\"0\")", "=TEXT(0.5,\"0\")", "=TEXT(2.675,\"0.00\")", "=TEXT(1.005,\"0.00\")",
        "=TEXT(-0.0001,\"0.000\")", "=TEXT(12,\"+0.000;-0.000;0.000\")", "=TEXT(-12,\"+0.000;-0.000;0.000\")",
        "=TEXT(0,\"+0.000;-0.000;0.000\")", "=TEXT(3.14159,\"0.0000\")", "=TEXT(1E20,\"0\")", "=TEXT(1E-20,\"0.00E+0\")",
        "=TEXT(12.5,\"00.000\")", "=TEXT(0.5,\"#.000\")", "=TEXT(1234.5,\"#,##0\")", "=TEXT(-1234.5,\"#,##0\")",
        "=TEXT(0.125,\"0.00%\")", "=TEXT(\"12.5\",\"0.0\")", "=TEXT(TRUE,\"0.0\")", "=TEXT(12.5,\"\")", "=TEXT(1/3,\"0.0##\")",
        "=FIXED(1234.567,1)", "=FIXED(-1234.567,-2)", "=FIXED(1234.5,0,TRUE)", "=FIXED(0.5,0)", "=FIXED(2.5,0)",
        "=FIXED(-0.5,0)", "=FIXED(1.005,2)", "=FIXED(2.675,2)", "=FIXED(1E15,2)", "=FIXED(-0.001,2)", "=FIXED(\"3.14159\")",
        "=FIXED(12345.678)", "=FIXED(12345.678,,TRUE)", "=FIXED(0.000001,8)",
        "=VALUE(\"1,5\")", "=VALUE(\" 3 \")", "=VALUE(\"1e3\")", "=VALUE(\"$1\")", "=VALUE(\"50%\")", "=VALUE(\"1,000\")",
        "=VALUE(\"1,000.5\")", "=VALUE(\"(5)\")", "=VALUE(\"-$1.50\")", "=VALUE(\"+3\")", "=VALUE(\"3-\")", "=VALUE(\".5\")",
        "=VALUE(\"5.\")", "=VALUE(\"1E+3\")", "=VALUE(\"\")", "=VALUE(\"abc\")", "=VALUE(\"12:30\")", "=VALUE(\"1 1/2\")",
        "=_xlfn.NUMBERVALUE(\"1,5\",\",\",\".\")", "=_xlfn.NUMBERVALUE(\"1.234,5\",\",\",\".\")",
        "=_xlfn.NUMBERVALUE(\"50%\")", "=_xlfn.NUMBERVALUE(\"50%%\")", "=_xlfn.NUMBERVALUE(\" 3 \")",
        "=_xlfn.NUMBERVALUE(\"1 000,5\",\",\",\" \")", "=_xlfn.NUMBERVALUE(\"\")", "=_xlfn.NUMBERVALUE(\"1e3\")",
        "=_xlfn.NUMBERVALUE(\"1,5\")", "=_xlfn.NUMBERVALUE(\"3,5\",\",\",\",\")",
        "=_xlfn.CONCAT(D!A1:A7)", "=_xlfn.CONCAT(1.5,\"-\",TRUE)", "=_xlfn.TEXTJOIN(\", \",TRUE,D!A1:A7)",
        "=_xlfn.TEXTJOIN(\"-\",FALSE,D!A1:A7)", "=_xlfn.TEXTJOIN(\"\",TRUE,1/4,\"a\",\"\",2)", "=CONCATENATE(1/3,\"|\",-0)",
        "=\"3\"+2", "=\"3\"*\"2\"", "=SUM(\"3\",2)", "=SUM(D!A1:A7)", "=\"1e3\"+0", "=\" 3 \"+0", "=\"1,000\"+0",
        "=\"$5\"+0", "=\"50%\"+0", "=\"abc\"+0", "=--\"-0\"", "=\"3\"=3", "=TRUE+1", "=SUM(TRUE,1)", "=AVERAGE(\"3\",5)",
        "=D!A1+D!A2", "=D!A1*2", "=D!A3+1", "=D!A4*2", "=D!A5+1", "=PRODUCT(D!A1:A7)", "=COUNT(D!A1:A7)",
        "=COUNTA(D!A1:A7)", "=AVERAGE(D!A1:A7)", "=MAX(D!A1:A7)", "=MAX(\"7\",2)", "=MIN(D!A1:A7,\"0.5\")",
        "=\"(5)\"+0", "=\"1/2\"*1", "=\"12:30\"*24", "=\"1 1/2\"+0", "=N(\"3\")", "=T(3)", "=LEN(1/3)", "=LEN(-0)",
        "=LEFT(1234.5,3)", "=MID(1/7,3,4)", "=UPPER(1E21)", "=LEN(2^0.5)", "=REPT(1.5,2)",
    ])
    save(wb, "text_numbers")


def schedule():
    wb, (s, h) = book("S", "H")
    import datetime
    for i, dt in enumerate(["2024-01-01", "2024-01-15", "2024-02-19", "2024-01-13", "2024-01-15", "2024-05-27"], start=1):
        h.cell(row=i, column=1, value=datetime.date.fromisoformat(dt))
    listed(s, [
        "=NETWORKDAYS(DATE(2024,1,1),DATE(2024,3,1),H!A1:A6)", "=NETWORKDAYS(DATE(2024,3,1),DATE(2024,1,1),H!A1:A6)",
        "=NETWORKDAYS(DATE(2024,1,13),DATE(2024,1,14))", "=NETWORKDAYS(DATE(2024,1,15),DATE(2024,1,15),H!A1:A6)",
        "=NETWORKDAYS(DATE(2024,1,1)+0.9,DATE(2024,1,31)+0.1)", "=NETWORKDAYS(DATE(2024,1,1),DATE(2024,1,31),DATE(2024,1,2))",
        "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),\"0000011\")", "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),7)",
        "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),17,H!A1:A6)", "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),\"1111111\")",
        "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),\"0000000\")", "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),8)",
        "=NETWORKDAYS.INTL(DATE(2024,1,1),DATE(2024,1,31),\"000001\")", "=NETWORKDAYS.INTL(DATE(2024,1,31),DATE(2024,1,1),1,H!A1:A6)",
        "=WORKDAY(DATE(2024,1,5),5,H!A1:A6)", "=WORKDAY(DATE(2024,1,20),-5,H!A1:A6)", "=WORKDAY(DATE(2024,1,6),0)",
        "=WORKDAY(DATE(2024,1,5),2.9)", "=WORKDAY(DATE(2024,1,5),-2.9)", "=WORKDAY(DATE(2024,1,13),1,H!A1:A6)",
        "=WORKDAY.INTL(DATE(2024,1,5),10,\"0010001\",H!A1:A6)", "=WORKDAY.INTL(DATE(2024,1,5),-10,11)",
        "=WORKDAY.INTL(DATE(2024,1,5),3,\"1111111\")", "=WORKDAY.INTL(DATE(2024,1,5),3,16)", "=WORKDAY(DATE(2024,1,5)+0.75,1)",
        "=EDATE(DATE(2024,3,31),-1)", "=EDATE(DATE(2024,3,31),-13)", "=EDATE(DATE(2024,1,31),1.9)", "=EDATE(DATE(2024,1,31),-1.9)",
        "=EDATE(DATE(2024,5,15)+0.5,0)", "=EOMONTH(DATE(2024,1,15),-1)", "=EOMONTH(DATE(2024,1,15),-12.7)",
        "=EOMONTH(DATE(2024,3,31),-1)", "=EOMONTH(DATE(2024,1,15),0.9)", "=EOMONTH(DATE(1900,1,15),-1)",
        "=DATEDIF(DATE(2024,1,31),DATE(2024,3,1),\"m\")", "=DATEDIF(DATE(2024,1,31),DATE(2024,3,1),\"md\")",
        "=DATEDIF(DATE(2024,1,31),DATE(2024,3,1),\"yd\")", "=DATEDIF(DATE(2023,3,1),DATE(2024,2,29),\"yd\")",
        "=DATEDIF(DATE(2023,3,1),DATE(2024,2,29),\"y\")", "=DATEDIF(DATE(2023,3,1),DATE(2024,2,29),\"ym\")",
        "=DATEDIF(DATE(2020,2,29),DATE(2021,2,28),\"y\")", "=DATEDIF(DATE(2020,2,29),DATE(2021,2,28),\"yd\")",
        "=DATEDIF(DATE(2020,2,29),DATE(2021,3,1),\"yd\")", "=DATEDIF(DATE(2023,5,31),DATE(2023,6,30),\"md\")",
        "=DATEDIF(DATE(2023,1,15),DATE(2023,1,15),\"d\")", "=DATEDIF(DATE(2023,1,15),DATE(2024,1,14),\"y\")",
        "=DATEDIF(DATE(2023,12,25),DATE(2024,1,5),\"yd\")", "=DATEDIF(DATE(2023,12,25),DATE(2024,1,5),\"YM\")",
        "=DATEDIF(DATE(2023,1,1)+0.9,DATE(2023,1,2)+0.1,\"d\")",
        "=WEEKNUM(DATE(2024,1,1))", "=WEEKNUM(DATE(2024,1,7),2)", "=WEEKNUM(DATE(2024,12,31),1)", "=WEEKNUM(DATE(2023,1,1),21)",
        "=WEEKNUM(DATE(2024,1,6),11)", "=WEEKNUM(DATE(2024,1,6),12)", "=WEEKNUM(DATE(2024,1,6),13)", "=WEEKNUM(DATE(2024,1,6),14)",
        "=WEEKNUM(DATE(2024,1,6),15)", "=WEEKNUM(DATE(2024,1,6),16)", "=WEEKNUM(DATE(2024,1,6),17)", "=WEEKNUM(DATE(2024,1,6),3)",
        "=_xlfn.ISOWEEKNUM(DATE(2021,1,1))", "=_xlfn.ISOWEEKNUM(DATE(2020,12,31))", "=_xlfn.ISOWEEKNUM(DATE(2024,12,30))",
        "=_xlfn.ISOWEEKNUM(DATE(2027,1,3))", "=WEEKDAY(DATE(2024,1,7),3)", "=WEEKDAY(DATE(2024,1,7),11)", "=WEEKDAY(DATE(2024,1,7),17)",
        "=WEEKDAY(DATE(2024,1,7),4)", "=TIME(25,0,0)", "=TIME(0,-1,0)", "=TIME(0,90,0)", "=TIME(23,59,60)", "=TIME(0,0,-1)",
        "=TIME(1,-30,0)", "=TIME(32768,0,0)", "=TIME(1.9,30.9,0.9)", "=HOUR(-0.5)", "=HOUR(1.75)", "=MINUTE(0.999999999)",
        "=SECOND(0.999999999)", "=HOUR(0.999999999)", "=SECOND(TIME(1,2,3)+0.4/86400)", "=SECOND(TIME(1,2,3)+0.6/86400)",
        "=HOUR(\"12:30\")", "=MINUTE(\"12:30:45\")", "=HOUR(\"25:00\")", "=HOUR(\"2:30 PM\")", "=TIMEVALUE(\"2:30 PM\")",
        "=TIMEVALUE(\"25:00\")", "=TIMEVALUE(\"2024-01-05 06:00\")", "=DAYS360(DATE(2024,1,31),DATE(2024,2,29))",
        "=DAYS360(DATE(2024,2,29),DATE(2024,3,31))", "=DAYS360(DATE(2024,2,29),DATE(2024,3,31),TRUE)",
        "=DAYS360(DATE(2023,2,28),DATE(2023,3,31))", "=YEARFRAC(DATE(2024,1,1),DATE(2024,7,1),0)",
        "=YEARFRAC(DATE(2024,1,1),DATE(2024,7,1),1)", "=YEARFRAC(DATE(2023,6,1),DATE(2024,7,1),1)",
        "=YEARFRAC(DATE(2024,1,1),DATE(2024,7,1),2)", "=YEARFRAC(DATE(2024,1,1),DATE(2024,7,1),3)",
        "=YEARFRAC(DATE(2024,1,31),DATE(2024,2,29),4)", "=YEARFRAC(DATE(2024,2,29),DATE(2024,1,31),0)",
        "=DATE(2024,-1,1)", "=DATE(99,1,1)", "=DATE(1900,2,29)", "=DATE(2024,1,-30)", "=DATE(2024.9,2.9,3.9)",
        "=DAY(60)", "=MONTH(60)", "=DAY(0)", "=WEEKDAY(60)", "=YEAR(2958465)", "=DATEVALUE(\"29-Feb-2024\")",
        "=DATEVALUE(\"2024/3/5\")", "=DATEVALUE(\"Mar 5, 2024\")", "=_xlfn.DAYS(DATE(2024,3,1),DATE(2024,2,1))",
    ])
    save(wb, "schedule")


def error_ranges():
    wb, (s, d) = book("E", "D")
    for i, v in enumerate([4, "=1/0", 7, "=NA()", "x", 2, None, "=SQRT(-1)", 9, True], start=1):
        if v is not None:
            d.cell(row=i, column=1, value=v)
    for i, v in enumerate([1, 2, 3, 4, 5, 6, 7, 8, 9, 10], start=1):
        d.cell(row=i, column=2, value=v)
    d.row_dimensions[3].hidden = True
    listed(s, [
        cse1("=SUM(IFERROR(D!A1:A10,0))"), cse1("=SUM(--ISERROR(D!A1:A10))"), cse1("=SUM(_xlfn.IFNA(D!A1:A10,100))"),
        "=SUMPRODUCT(--ISERROR(D!A1:A10))", "=SUMPRODUCT(ISNA(D!A1:A10)*1)", "=SUMPRODUCT(--ISERR(D!A1:A10))",
        "=COUNTIF(D!A1:A10,\"#N/A\")", "=COUNTIF(D!A1:A10,\"#DIV/0!\")", "=COUNTIF(D!A1:A10,\"<>#N/A\")",
        "=_xlfn.IFNA(VLOOKUP(99,D!B1:B10,1,FALSE),\"none\")", "=_xlfn.IFNA(1/0,1)", "=IFERROR(\"\",1)", "=IFERROR(D!A7,1)",
        "=IFERROR(D!A7,1)&\"\"", "=ISERROR(D!A1:A10)", "=SUMPRODUCT(--ISNUMBER(D!A1:A10))",
        "=_xlfn.AGGREGATE(9,6,D!A1:A10)", "=_xlfn.AGGREGATE(4,6,D!A1:A10)", "=_xlfn.AGGREGATE(14,6,D!A1:A10,2)", "=_xlfn.AGGREGATE(15,6,D!A1:A10,1)",
        "=_xlfn.AGGREGATE(1,6,D!A1:A10)", "=_xlfn.AGGREGATE(2,6,D!A1:A10)", "=_xlfn.AGGREGATE(3,6,D!A1:A10)", "=_xlfn.AGGREGATE(12,6,D!A1:A10)",
        "=_xlfn.AGGREGATE(16,6,D!A1:A10,0.5)", "=_xlfn.AGGREGATE(9,0,D!A1:A10)", "=_xlfn.AGGREGATE(9,5,D!B1:B10)", "=_xlfn.AGGREGATE(9,7,D!A1:A10)",
        "=_xlfn.AGGREGATE(9,1,D!B1:B10)", "=_xlfn.AGGREGATE(9,3,D!A1:A10)", "=_xlfn.AGGREGATE(19,6,D!A1:A10)", "=_xlfn.AGGREGATE(9,8,D!B1:B10)",
        "=_xlfn.AGGREGATE(14,6,D!B1:B10/(D!B1:B10>4),1)", "=_xlfn.AGGREGATE(15,6,D!B1:B10/(MOD(D!B1:B10,3)=0),2)",
        "=_xlfn.AGGREGATE(5,6,D!A1:A10)", "=_xlfn.AGGREGATE(6,6,D!A1:A10)", "=_xlfn.AGGREGATE(7,6,D!A1:A10)", "=_xlfn.AGGREGATE(8,6,D!A1:A10)",
        "=_xlfn.AGGREGATE(10,6,D!A1:A10)", "=_xlfn.AGGREGATE(11,6,D!A1:A10)", "=_xlfn.AGGREGATE(13,6,D!B1:B10)", "=_xlfn.AGGREGATE(17,6,D!A1:A10,1)",
        "=_xlfn.AGGREGATE(18,6,D!A1:A10,0.25)", "=_xlfn.AGGREGATE(19,6,D!A1:A10,0.25)", "=_xlfn.AGGREGATE(14,6,D!A1:A10,10)",
        "=SUBTOTAL(9,D!A1:A10)", "=SUBTOTAL(109,D!B1:B10)", "=SUBTOTAL(9,D!B1:B10)", "=SUBTOTAL(2,D!A1:A10)",
        "=SUBTOTAL(3,D!A1:A10)", "=SUM(D!A1:A10)", "=MAX(D!A1:A10)", "=COUNT(D!A1:A10)", "=COUNTA(D!A1:A10)",
        "=COUNTBLANK(D!A1:A10)", "=SUM({1,#N/A})", "=SUMPRODUCT(--ISERROR({1,#N/A,#DIV/0!}))", "=INDEX({1,#N/A},2)",
        "=ISNA(INDEX({1,#N/A},2))", "=ERROR.TYPE(NA())", "=ERROR.TYPE(1/0)", "=ERROR.TYPE(1)", "=ERROR.TYPE(D!A8)",
        "=ERROR.TYPE(#REF!)", "=ERROR.TYPE(#NULL!)", "=ERROR.TYPE(#NAME?)", "=ERROR.TYPE(#NUM!)", "=ERROR.TYPE(#VALUE!)",
        "=ISERR(NA())", "=ISERR(1/0)", "=ISERROR(\"#N/A\")", "=IFERROR(1/0,1/0)", "=IFERROR(NA(),\"\")",
        "=MATCH(7,D!A1:A10,0)", "=VLOOKUP(7,D!A1:A10,1,FALSE)", "=VLOOKUP(9,D!A1:A10,1)", "=SUMIF(D!A1:A10,\">3\")",
        "=COUNTIF(D!A1:A10,\">3\")", "=AVERAGEIF(D!A1:A10,\"<>x\",D!B1:B10)", "=SUMIF(D!B1:B10,\">5\",D!A1:A10)",
        "=_xlfn.MAXIFS(D!B1:B10,D!A1:A10,\"<>#N/A\")", "=LARGE(D!A1:A10,1)", "=RANK(7,D!A1:A10)", "=PRODUCT(IFERROR(1/0,2),3)",
        cse1("=MAX(IF(ISNUMBER(D!A1:A10),D!A1:A10))"), cse1("=SUM(IF(ISERROR(D!A1:A10),1,0))"),
        cse1("=COUNT(IFERROR(1/D!A1:A10,\"\"))"), cse1("=INDEX(IFERROR(D!A1:A10,-1),2)"),
    ])
    save(wb, "error_ranges")


def design_more():
    wb, (s, d) = book("M", "Data Sheet")
    xs = [10, 20, 30, 40, 50, 60]
    ys = [2.1, 3.9, 6.2, 7.8, 10.1, 12.2]
    for i, (x, y) in enumerate(zip(xs, ys), start=1):
        d.cell(row=i, column=1, value=x)
        d.cell(row=i, column=2, value=y)
    for i, v in enumerate(["M6", "m8", "bolt", "Bolt M10", None, "b", "c*d", 12, "12", "apple pie"], start=1):
        if v is not None:
            d.cell(row=i, column=3, value=v)
    for r, row in enumerate([[2, 1, 0], [1, 3, 1], [0, 1, 4]], start=1):
        for c, v in enumerate(row, start=5):
            d.cell(row=r, column=c, value=v)
    listed(s, [
        "=CONVERT(1,\"in\",\"mm\")", "=CONVERT(25.4,\"mm\",\"in\")", "=CONVERT(100,\"F\",\"C\")", "=CONVERT(0,\"C\",\"K\")",
        "=CONVERT(1,\"lbm\",\"kg\")", "=CONVERT(1,\"ft\",\"m\")", "=CONVERT(1,\"lbf\",\"N\")", "=CONVERT(1,\"hp\",\"W\")",
        "=CONVERT(1,\"mi\",\"km\")", "=CONVERT(1,\"psi\",\"Pa\")", "=CONVERT(1,\"bar\",\"Pa\")", "=CONVERT(1,\"atm\",\"mmHg\")",
        "=CONVERT(1,\"gal\",\"l\")", "=CONVERT(1,\"ozm\",\"g\")", "=CONVERT(1,\"yd\",\"ft\")", "=CONVERT(1,\"um\",\"mm\")",
        "=CONVERT(1,\"kW\",\"hp\")", "=CONVERT(1,\"Nm\",\"J\")", "=CONVERT(1,\"rpm\",\"Hz\")", "=CONVERT(1,\"in\",\"kg\")",
        "=CONVERT(1,\"ang\",\"m\")", "=CONVERT(1,\"cm2\",\"m2\")", "=CONVERT(1,\"in3\",\"cm3\")", "=CONVERT(1,\"kcal\",\"J\")",
        "=CONVERT(1,\"Btu\",\"J\")", "=CONVERT(1,\"mph\",\"m/s\")", "=CONVERT(1,\"m/h\",\"m/s\")", "=CONVERT(1,\"deg\",\"rad\")",
        "=SLOPE('Data Sheet'!B1:B6,'Data Sheet'!A1:A6)", "=INTERCEPT('Data Sheet'!B1:B6,'Data Sheet'!A1:A6)",
        "=FORECAST(35,'Data Sheet'!B1:B6,'Data Sheet'!A1:A6)", "=RSQ('Data Sheet'!B1:B6,'Data Sheet'!A1:A6)",
        "=CORREL('Data Sheet'!B1:B6,'Data Sheet'!A1:A6)", "=STEYX('Data Sheet'!B1:B6,'Data Sheet'!A1:A6)",
        "=INDEX(LINEST('Data Sheet'!B1:B6,'Data Sheet'!A1:A6),1)", "=INDEX(LINEST('Data Sheet'!B1:B6,'Data Sheet'!A1:A6),2)",
        "=INDEX(LINEST('Data Sheet'!B1:B6,'Data Sheet'!A1:A6^{1,2}),1,1)", "=TREND('Data Sheet'!B1:B6,'Data Sheet'!A1:A6,45)",
        "=GROWTH('Data Sheet'!B1:B6,'Data Sheet'!A1:A6,45)", "=STDEV('Data Sheet'!B1:B6)", "=STDEVP('Data Sheet'!B1:B6)",
        "=PERCENTILE('Data Sheet'!B1:B6,0.9)", "=QUARTILE('Data Sheet'!B1:B6,3)", "=MEDIAN('Data Sheet'!B1:B6)",
        "=RANK(7.8,'Data Sheet'!B1:B6)", "=RANK(7.8,'Data Sheet'!B1:B6,1)", "=LARGE('Data Sheet'!C1:C10,1)",
        "=SMALL('Data Sheet'!A1:B6,3)", "=PERCENTRANK('Data Sheet'!B1:B6,7)", "=AVEDEV('Data Sheet'!B1:B6)", "=DEVSQ('Data Sheet'!B1:B6)",
        "=SINH(1)", "=COSH(-1)", "=TANH(0.5)", "=ASINH(1)", "=ACOSH(0.5)", "=ATANH(1)", "=_xlfn.COT(0)", "=_xlfn.SEC(PI())",
        "=_xlfn.CSC(PI()/2)", "=LOG(8,2)", "=LOG(-1)", "=LN(0)", "=LOG10(0.001)", "=EXP(710)", "=SQRTPI(2)", "=LOG(10,1)",
        "=DEC2HEX(255)", "=DEC2HEX(-1)", "=DEC2HEX(255,4)", "=HEX2DEC(\"FFFFFFFFFF\")", "=BIN2DEC(\"1111111111\")",
        "=DEC2BIN(-1)", "=DEC2BIN(512)", "=DEC2OCT(-8)", "=HEX2BIN(\"F\",8)", "=_xlfn.BITAND(12,10)", "=_xlfn.BITLSHIFT(1,4)",
        "=ROMAN(1999)", "=_xlfn.ARABIC(\"MCMXCIX\")", "=_xlfn.BASE(255,16,4)", "=_xlfn.DECIMAL(\"FF\",16)", "=MDETERM('Data Sheet'!E1:G3)",
        "=INDEX(MINVERSE('Data Sheet'!E1:G3),2,2)", "=INDEX(MMULT('Data Sheet'!E1:G3,'Data Sheet'!E1:G3),3,3)",
        "=SUMPRODUCT(MMULT('Data Sheet'!E1:G3,{1;1;1}))", "=SUMX2MY2('Data Sheet'!A1:A3,'Data Sheet'!B1:B3)",
        "=SUMXMY2('Data Sheet'!A1:A3,'Data Sheet'!B1:B3)", "=SERIESSUM(0.5,0,1,{1,1,1,1})", "=MULTINOMIAL(2,3)",
        "=FACTDOUBLE(7)", "=PERMUT(5,2)", "=COMBIN(10,3)", "=_xlfn.COMBINA(4,3)",
        "=INDIRECT(\"'Data Sheet'!B\"&3)", "=INDIRECT(\"'Data Sheet'!R2C1\",FALSE)", "=SUM(INDIRECT(\"'Data Sheet'!A1:A\"&4))",
        "=OFFSET('Data Sheet'!A1,2,1)", "=SUM(OFFSET('Data Sheet'!A1,1,0,3,2))", "=ROWS(OFFSET('Data Sheet'!A1,0,0,5))",
        "=ADDRESS(2,3)", "=ADDRESS(2,3,4)", "=ADDRESS(2,3,1,FALSE)", "=ADDRESS(2,3,1,TRUE,\"Data Sheet\")", "=ADDRESS(2,28,2)",
        "=COUNTIF('Data Sheet'!C1:C10,\">b\")", "=COUNTIF('Data Sheet'!C1:C10,\"<=M6\")", "=COUNTIF('Data Sheet'!C1:C10,\"*\")",
        "=COUNTIF('Data Sheet'!C1:C10,\"<>*\")", "=COUNTIF('Data Sheet'!C1:C10,\"c~*d\")", "=COUNTIF('Data Sheet'!C1:C10,\"12\")",
        "=COUNTIF('Data Sheet'!C1:C10,\">10\")", "=COUNTIF('Data Sheet'!C1:C10,\"?\")", "=COUNTIF('Data Sheet'!C1:C10,\"*M*\")",
        "=COUNTIF('Data Sheet'!C1:C10,'Data Sheet'!C5)", "=COUNTIF('Data Sheet'!C1:C10,\"=\"&'Data Sheet'!C5)",
        "=SEARCH(\"m?\",\"Bolt M10\")", "=SEARCH(\"*10\",\"Bolt M10\")", "=FIND(\"M\",\"Bolt M10\")", "=SEARCH(\"~*\",\"c*d\")",
        "=SUBSTITUTE(\"a-b-c\",\"-\",\"+\",2)", "=REPLACE(\"M10x1.5\",1,3,\"M12\")", "=TRIM(\"  a   b  \")", "=PROPER(\"bolt m10-x\")",
        "=MID(\"Bolt\",0,2)", "=MID(\"Bolt\",10,2)", "=LEFT(\"Bolt\",10)", "=RIGHT(123.45,3)", "=TEXT(DATE(2024,3,5),\"mmm d, yyyy\")",
        "=TEXT(0.75,\"h:mm AM/PM\")", "=TEXT(1.5,\"[h]\"\"h\"\" mm\"\"m\"\"\")", "=TEXT(-0.25,\"0.00;(0.00)\")", "=TEXT(1234.5,\"0.0,\")",
        "=TEXT(0.000125,\"0.0E+0\")", "=TEXT(125000,\"0.0E+00\")", "=TEXT(3.5,\"# ?/?\")", "=TEXT(30,\"0\"\"°\"\"\")",
        "=DOLLAR(1234.567,2)", "=DOLLAR(-0.5)", "=EXACT(\"a\",\"A\")", "=CODE(\"A\")", "=CHAR(176)", "=CLEAN(\"a\"&CHAR(7)&\"b\")",
        "=_xlfn.SWITCH(2,1,\"a\",2,\"b\",\"c\")", "=_xlfn.IFS(1>2,\"a\",TRUE,\"b\")", "=CHOOSE(1.9,\"a\",\"b\")", "=IF(\"\",1,2)", "=IF(\"TRUE\",1,2)",
        "=IF(0.0000001,1,2)", "=AND(\"TRUE\",1)", "=OR('Data Sheet'!C1:C3)", "=_xlfn.XOR(TRUE,1,0)", "=NOT(\"FALSE\")", "=N(TRUE)",
        "=ISNUMBER(\"1\")", "=ISTEXT(1)", "=ISBLANK('Data Sheet'!C5)", "=ISEVEN(2.9)", "=ISODD(-3)", "=ISLOGICAL(\"TRUE\")",
        "=TYPE({1,2})", "=TYPE(\"a\")", "=TYPE(TRUE)", "=TYPE(1/0)",
    ])
    save(wb, "design_more")


# Legacy (pre-dynamic-array) formulas: a range where a function wants one value is cut to the
# formula's row, except in parameters that take arrays (SUMPRODUCT, LOOKUP's vectors, INDEX's
# array…). Each formula is written in rows 3 (inside the data's rows) and 9 (outside).
IMPLICIT = [
    "=MATCH(1,(A1:A6=\"b\")*(B1:B6=2),0)", "=MATCH(1,INDEX((A1:A6=\"b\")*(B1:B6=2),0),0)", "=SUM(B1:B6*C1:C6)",
    "=SUM((B1:B6>1)*1)", "=MAX(IF(B1:B6>1,C1:C6))", "=LOOKUP(2,1/(A1:A6=\"b\"),C1:C6)", "=COUNT(1/(B1:B6>1))",
    "=SUMPRODUCT((B1:B6>1)*C1:C6)", "=AND(B1:B6>0)", "=B1:B6*2", "=ABS(B1:B6)", "=B1:B6", "=A1:A6&\"x\"",
    "=INDEX(C1:C6,MATCH(\"b\",A1:A6,0))", "=VLOOKUP(A1:A6,A1:C6,3,FALSE)", "=IF(B1:B6>1,\"big\",\"small\")",
    "=SUMIF(A1:A6,A1:A6,C1:C6)", "=ROUND(C1:C6,0)", "=N(B1:B6)", "=ROWS(B1:B6*2)", "=SUM(B1:B6)", "=MIN(B1:B6*C1:C6)",
    "=INDEX(B1:B6*C1:C6,2)", "=SUMPRODUCT(B1:B6,C1:C6)", "=COUNTIF(B1:B6,B1:B6)", "=ISNUMBER(B1:B6)", "=LEN(A1:A6)",
    "=SUM(IF(A1:A6=\"b\",C1:C6,0))", "=AVERAGE(IF(B1:B6>1,C1:C6))", "=TEXT(C1:C6,\"0.0\")", "=B:B", "=SUM(B:B*1)",
    "=MMULT(TRANSPOSE(B1:B6),C1:C6)", "=SUMPRODUCT(--(A1:A6=\"b\"),C1:C6)", "=MATCH(MAX(C1:C6*(A1:A6=\"b\")),C1:C6,0)",
    "=B2:D2", "=SUM(B2:D2*2)", "=2:2", "=OR(A1:A6=\"c\")", "=CONCATENATE(A1:A6)",
]


def implicit():
    wb, (s,) = book("I")
    for r, (a, b, c) in enumerate([("a", 1, 1.5), ("b", 2, 2.5), ("c", 3, 3.5), ("b", 4, 4.5), ("a", 0, 5.5), ("d", -1, 6.5)],
                                  start=1):
        s.cell(row=r, column=1, value=a)
        s.cell(row=r, column=2, value=b)
        s.cell(row=r, column=3, value=c)
    for k, fo in enumerate(IMPLICIT):
        col = 6 + 2 * k
        s.cell(row=3, column=col, value=fo)
        s.cell(row=9, column=col, value=fo)
        s.cell(row=12, column=col, value=fo[1:])
    save(wb, "implicit")


def compare_criteria():
    wb, (s, d) = book("C", "D")
    for i, (a, b) in enumerate([(1, "a"), (2, "b"), (2, "c"), (2, "d"), (3, "e"), (None, "f"), (5, "g"), ("x", "h"),
                                (7, "i"), (" 8", "j")], start=1):
        if a is not None:
            d.cell(row=i, column=1, value=a)
        d.cell(row=i, column=2, value=b)
    for i, v in enumerate([10, 20, 30, 40, 50, 60, 70, 80, 90, 100], start=1):
        d.cell(row=i, column=3, value=v)
    for i, v in enumerate(["a-b", "ab", "a b", "A", "a", "B", "_x", "10", "9", ""], start=1):
        if v != "":
            d.cell(row=i, column=4, value=v)
    listed(s, [
        "=VLOOKUP(2,D!A1:B5,2,TRUE)", "=MATCH(2,D!A1:A5,1)", "=MATCH(2,D!A1:A5,0)", "=VLOOKUP(4,D!A1:B7,2)",
        "=VLOOKUP(6,D!A1:B9,2)", "=LOOKUP(2,D!A1:A5,D!B1:B5)", "=MATCH(2.5,{1,2,2,2,3})", "=HLOOKUP(2,{1,2,2,3;\"a\",\"b\",\"c\",\"d\"},2)",
        "=SUMIF(D!A1:A10,\">1\",D!C1)", "=SUMIF(D!A1:A10,2,D!C1:C2)", "=SUMIF(D!A1:A5,2,D!C3:C3)", "=AVERAGEIF(D!A1:A10,2,D!C1)",
        "=COUNTIFS(D!A1:A10,\">1\",D!C1:C5,\">0\")", "=SUMIFS(D!C1:C10,D!A1:A5,2)", "=COUNTIF(D!A1:A10,\">\")",
        "=COUNTIF(D!A1:A10,\"<\")", "=COUNTIF(D!A1:A10,\"=\")", "=COUNTIF(D!A1:A10,\"<>\")", "=COUNTIF(D!A1:A10,\" 8\")",
        "=COUNTIF(D!A1:A10,8)", "=COUNTIF(D!A1:A10,\">=2\")", "=COUNTIF(D!A1:A10,\">=\"&D!A6)", "=COUNTIF(D!A1:A10,D!A6)",
        "=COUNTIF(D!D1:D10,\"a*\")", "=COUNTIF(D!D1:D10,\">a\")", "=COUNTIF(D!D1:D10,\"<b\")", "=COUNTIF(D!D1:D10,\">9\")",
        "=COUNTIF(D!D1:D10,\"<>a\")", "=COUNTIF(D!D1:D10,\"a?b\")", "=COUNTIF(D!D1:D10,\"<=\"&\"ab\")",
        "=\"a\"<\"B\"", "=\"a\"=\"A\"", "=\"10\">\"9\"", "=\"a-b\"<\"ab\"", "=\"a b\"<\"ab\"", "=\"_x\"<\"a\"", "=TRUE>1", "=\"a\">1",
        "=FALSE<TRUE", "=\"\"<\"a\"", "=D!A6=0", "=D!A6=\"\"", "=D!A6<1", "=D!A6>\"\"", "=\"1\"=1", "=1=1.0000000000000002",
        "=0.1+0.2=0.3", "=(0.1+0.2)-0.3=0", "=1E-16=0", "=10%^2", "=-D!A7^2", "=2^-2", "=-2^-2", "=5%%", "=2*-3^2",
        "=\"a\"&1=\"a1\"", "=1&2+3", "=1+2&3", "=\"x\"&-1", "=10-5-2", "=2^3^2", "=-(-2)^2", "=1/3*3=1", "=ROUND(1/3,15)*3",
        "=D!A1:A3=2", "=SUM((D!A1:A5=2)*1)", "=MAX(D!D1:D10)", "=MIN(\"10\",D!D8)", "=CODE(D!D7)", "=MATCH(\"b\",D!D1:D10,0)",
        "=MATCH(\"B\",D!D1:D10,0)", "=MATCH(\"a b\",D!D1:D10,0)", "=MATCH(\"10\",D!D1:D10,0)", "=MATCH(10,D!D1:D10,0)",
        "=VLOOKUP(\"ab\",D!D1:D6,1,FALSE)", "=OFFSET(D!A1,0,0,0,1)", "=OFFSET(D!A1,-1,0)", "=SUM(OFFSET(D!C1,2,0,-2,1))",
        "=INDEX(D!A1:C10,0,3)", "=SUM(INDEX(D!A1:C10,2,0))", "=INDEX(D!A1:C10,11,1)", "=INDEX(D!A1:C10,1,4)",
        "=INDEX((D!A1:A3,D!C1:C3),2,1,2)", "=AREAS((D!A1:A3,D!C1:C3))", "=ROW(INDEX(D!A1:A10,4))", "=SUM(D!A1:INDEX(D!A1:A10,4))",
    ])
    save(wb, "compare_criteria")


# Formulas as engineers type them: spaces and line breaks (Alt+Enter) between tokens, which
# Excel keeps in the file; a space between two references is the intersection operator.
SPACING = [
    "=SUM( A1 , B1 )", "= A1+B1", "=A1 +\nB1", "=IF(A1>0 ,\n  \"pos\" ,\n  \"neg\" )", "=A1 * 2", "= - 2", "=A1 - -B1",
    "=SUM(A1:B2 B1:C3)", "=SUM(A1:A3 )", "=SUM( A1:A3)", "=(A1:C1 B1:B3)", "=ROUND( PI( ) , 3 )", "=\tA1+1",
    "=A1\r\n+1", "=SUM(A1:A3,\n B1:B3)", "=IF( A1 = 1 , \"one\" , \"other\" )", "={1 , 2 , 3}", "=SUM({1 ,2; 3, 4})",
    "=MAX( (A1:A3) )", "=\"a \" & \" b\"", "=A1 %", "=2 ^ 3", "=INDEX( A1:C3 , 2 , 3 )", "=A1:A3 A2:C2",
    "=SUM((A1:A3 A2:C2))", "=ISREF(A1 B1)", "=ISERROR(A1 B2)", "=A1  +  B1", "=COUNT(A1:C3 )",
]


def spacing():
    wb, (s,) = book("S")
    for r in range(1, 4):
        for c in range(1, 4):
            s.cell(row=r, column=c, value=r * 10 + c)
    for i, fo in enumerate(SPACING, start=1):
        s.cell(row=i, column=5, value=fo)
        s.cell(row=i, column=6, value=repr(fo))
    save(wb, "spacing")


def stats_edges():
    wb, (s, d) = book("St", "D")
    for i, v in enumerate([3, 1, 4, 1, 5, 9, 2, 6, "x", True, None, 5], start=1):
        if v is not None:
            d.cell(row=i, column=1, value=v)
    for i, v in enumerate([2.5, 3.5, 1.5, 4.5], start=1):
        d.cell(row=i, column=2, value=v)
    listed(s, [
        "=LARGE(D!A1:A12,1.5)", "=SMALL(D!A1:A12,2.1)", "=LARGE(D!A1:A12,0)", "=SMALL(D!A1:A12,9)", "=LARGE(D!A1:A12,9)",
        "=PERCENTILE(D!A1:A12,0)", "=PERCENTILE(D!A1:A12,1)", "=PERCENTILE(D!A1:A12,1.1)", "=_xlfn.PERCENTILE.EXC(D!A1:A12,0.1)",
        "=_xlfn.PERCENTILE.EXC(D!A1:A12,0.5)", "=QUARTILE(D!A1:A12,4)", "=QUARTILE(D!A1:A12,5)", "=QUARTILE(D!A1:A12,2.7)",
        "=_xlfn.QUARTILE.EXC(D!A1:A12,1)", "=MEDIAN(D!A1:A12)", "=MODE(D!A1:A12)", "=_xlfn.MODE.SNGL(D!B1:B4)", "=RANK(1,D!A1:A12)",
        "=RANK(5,D!A1:A12)", "=_xlfn.RANK.AVG(1,D!A1:A12)", "=_xlfn.RANK.AVG(5,D!A1:A12,1)", "=RANK(7,D!A1:A12)", "=_xlfn.RANK.EQ(9,D!A1:A12)",
        "=STDEV(D!A1:A12)", "=STDEV(3,1,\"4\",TRUE)", "=STDEVA(D!A1:A12)", "=VAR(D!A1:A1)", "=VARA(D!A1:A12)", "=STDEVPA(D!A1:A12)",
        "=AVERAGEA(D!A1:A12)", "=MAXA(D!A1:A12)", "=MINA(D!A1:A12)", "=COUNTA(D!A1:A12)", "=COUNTBLANK(D!A1:A12)",
        "=TRIMMEAN(D!A1:A12,0.2)", "=TRIMMEAN(D!A1:A12,0.25)", "=GEOMEAN(D!A1:A12)", "=HARMEAN(D!A1:A12)", "=KURT(D!A1:A12)",
        "=SKEW(D!A1:A12)", "=PERCENTRANK(D!A1:A12,4)", "=PERCENTRANK(D!A1:A12,4.5,2)", "=_xlfn.PERCENTRANK.EXC(D!A1:A12,4)",
        "=STANDARDIZE(5,4,2)", "=NORMDIST(1,0,1,TRUE)", "=NORMSINV(0.975)", "=_xlfn.NORM.INV(0.9,10,2)", "=TDIST(2,10,2)", "=TINV(0.05,10)",
        "=CONFIDENCE(0.05,2,50)", "=CHIDIST(3,2)", "=FDIST(2,3,10)", "=BINOMDIST(3,10,0.5,FALSE)", "=POISSON(2,3,TRUE)",
        "=EXPONDIST(1,2,TRUE)", "=WEIBULL(1,2,3,TRUE)", "=GAMMADIST(2,3,1,TRUE)", "=LOGNORMDIST(2,0,1)", "=CORREL(D!A1:A4,D!B1:B4)",
        "=COVAR(D!A1:A4,D!B1:B4)", "=_xlfn.COVARIANCE.S(D!A1:A4,D!B1:B4)", "=PEARSON(D!A1:A4,D!B1:B4)", "=SUMPRODUCT(LARGE(D!A1:A12,{1,2,3}))",
        "=SUM(SMALL(D!A1:A12,{1,2}))", "=INDEX(FREQUENCY(D!A1:A12,{2,4}),3)", "=SUM(FREQUENCY(D!A1:A12,{2,4}))",
        "=ROWS(FREQUENCY(D!A1:A12,{2,4}))", "=MAX(D!A1:A12,\"10\")", "=SUM(D!A9:A10)", "=PRODUCT(D!A9:A11)", "=AVERAGE(D!A9:A11)",
        "=FISHER(0.5)", "=FISHERINV(0.5)", "=GAMMALN(4)", "=FACT(170)", "=FACT(171)", "=COMBIN(1030,515)", "=DEVSQ(D!A1:A12)",
    ])
    save(wb, "stats_edges")


def date_formats():
    wb, (s,) = book("F")
    values = [45292.75, 45351.0, 45658.999994, 0.5, 1.25, 45000.0001, 45382.5208333333, 2.75]
    fmts = ["ddd dd-mmm", "yyyy-mm-dd hh:mm:ss", "[$-409]mmmm d, yyyy;@", "m/d/yyyy h:mm AM/PM", "hh:mm:ss.000", "[mm]",
            "d-mmm", "mmmmm", "dddd", "yy", "h:mm", "h:mm:ss AM/PM", "[h]:mm", "[ss]", "mm/dd", "d.m.yyyy", "hh\"h\"mm",
            "dd/mm/yyyy hh:mm", "mmm-yy", "h AM/PM", "s.00", "yyyy\"-W\"", "ddd, mmm d", "[h]:mm:ss.0", "m", "mm:ss", "A/P h"]
    text_table(s, values, fmts)
    save(wb, "date_formats")


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
lookups()
rounding()
trig_criteria()
text_numbers()
schedule()
error_ranges()
design_more()
implicit()
compare_criteria()
spacing()
stats_edges()
date_formats()
