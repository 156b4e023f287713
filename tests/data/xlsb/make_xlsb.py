#!/usr/bin/env python3
"""Writes an Excel binary workbook (.xlsb, [MS-XLSB]) from an Excel-saved .xlsx, keeping each
formula it can compile to Ptg tokens AND the value Excel cached for it.

Why: no Excel-saved .xlsb is at hand, LibreOffice cannot write .xlsb and SheetJS's XLSB writer
(npm `xlsx` 0.18.5) writes values only (its write_ws_bin_cell has no BrtFmla* records). This
writer is independent of the reader under test (calamine): the record layouts follow
[MS-XLSB] 2.4 (records) and 2.5.98 (formulas), the function numbers come from xlwt's BIFF
table (the Ftab of [MS-XLS] 2.5.198.17, which [MS-XLSB] 2.5.98.10 continues) plus the
2007 functions of the XLSB Ftab, and formulas are lexed by openpyxl's tokenizer.

What it compiles: numbers, strings, booleans, errors, cell and area references (whole columns
and rows too) on the same sheet or another (PtgRef3d/PtgArea3d through BrtExternSheet), defined
names (BrtName, PtgName), the operators (+ - * / ^ & = <> < > <= >= unary - + and %),
parentheses, missing arguments, the built-in functions of the Ftab and `_xlfn.` functions (a
hidden future-function name and PtgFuncVar 255). A block of cells sharing one formula in the
source is written as a shared formula (PtgExp and BrtShrFmla with PtgRefN/PtgAreaN), an array
formula as BrtArrFmla after its first cell, each of its cells PtgExp. What it
does not compile (an array constant, a data table, `_xlws.`/`_xlpm.` functions, a function
not in the Ftab, the intersection operator) is written as the value Excel cached, a constant,
and listed on stderr.

The optional parts and tokens Excel adds are left out: a styles.bin of one XF (every cell General),
no PtgAttr tokens (PtgAttrIf, PtgAttrSpace…), no calc chain. Strings go to sharedStrings.bin.

Usage: make_xlsb.py SOURCE.xlsx OUT.xlsb OUT.formulas.tsv
The .tsv lists each formula written (sheet, cell, formula) for the test.
"""

import re
import struct
import sys
import xml.etree.ElementTree as ET
import zipfile

from openpyxl import load_workbook
from openpyxl.formula.tokenizer import Token, Tokenizer
from openpyxl.utils.cell import column_index_from_string, coordinate_from_string
from openpyxl.worksheet.formula import ArrayFormula, DataTableFormula
from xlwt import ExcelMagic

MAIN_NS = "{http://schemas.openxmlformats.org/spreadsheetml/2006/main}"
REL_NS = "{http://schemas.openxmlformats.org/officeDocument/2006/relationships}"

# [MS-XLSB] 2.5.98.10 Ftab entries past the BIFF8 table (Excel 2007's functions):
# name -> (iftab, least arguments, most arguments).
FTAB_2007 = {
    "IFERROR": (480, 2, 2),
    "COUNTIFS": (481, 2, 254),
    "SUMIFS": (482, 3, 255),
    "AVERAGEIF": (483, 2, 3),
    "AVERAGEIFS": (484, 3, 255),
}

# [MS-XLSB] 2.5.98.2 BErr.
ERRORS = {"#NULL!": 0x00, "#DIV/0!": 0x07, "#VALUE!": 0x0F, "#REF!": 0x17, "#NAME?": 0x1D, "#NUM!": 0x24, "#N/A": 0x2A}

# Binary operators by precedence (lowest first); [MS-XLSB] 2.5.98.16 Ptg numbers.
BINARY = [
    {"=": 0x0B, "<>": 0x0E, "<": 0x09, "<=": 0x0A, ">=": 0x0C, ">": 0x0D},
    {"&": 0x08},
    {"+": 0x03, "-": 0x04},
    {"*": 0x05, "/": 0x06},
    {"^": 0x07},
]
PTG_UPLUS, PTG_UMINUS, PTG_PERCENT, PTG_PAREN, PTG_MISSARG = 0x12, 0x13, 0x14, 0x15, 0x16
PTG_STR, PTG_ERR, PTG_BOOL, PTG_INT, PTG_NUM = 0x17, 0x1C, 0x1D, 0x1E, 0x1F
# Value-class forms of PtgFunc, PtgFuncVar, PtgRef, PtgArea; the reference class is 0x20 less.
PTG_FUNC_V, PTG_FUNCVAR_V, PTG_REF_V, PTG_AREA_V = 0x41, 0x42, 0x44, 0x45
# PtgName, PtgRefN, PtgAreaN, PtgRef3d, PtgArea3d (value class) and PtgExp.
PTG_NAME_V, PTG_REFN_V, PTG_AREAN_V, PTG_REF3D_V, PTG_AREA3D_V, PTG_EXP = 0x43, 0x4C, 0x4D, 0x5A, 0x5B, 0x01
# The user-defined function number of PtgFuncVar: the function is the name on the stack first.
USER_FUNCTION = 0xFF
# BrtName's flags ([MS-XLSB] 2.4.711): fHidden, fFunc, fProc, fFutureFunction.
NAME_HIDDEN, NAME_FUNC, NAME_PROC, NAME_FUTURE = 0x1, 0x2, 0x8, 0x20000
# The last row and column of a sheet: a reference over all of them is a whole column or row.
LAST_ROW, LAST_COL = 0xFFFFF, 0x3FFF


class Unsupported(Exception):
    """A formula this writer does not compile; the message says why."""


class NotShareable(Unsupported):
    """A shared formula this writer writes cell by cell instead (a reference to another sheet)."""


# ---------------------------------------------------------------- formulas to Ptg tokens


def function_entry(name):
    """(iftab, least, most) of a built-in function, or Unsupported."""
    if name in FTAB_2007:
        return FTAB_2007[name]
    entry = ExcelMagic.all_funcs_by_name.get(name)
    if entry is None or entry[0] < 0:
        # Not in the table, or an add-in function (-1: BIFF calls it through a name).
        raise Unsupported(f"function {name} is not in the Ftab")
    return entry[0], entry[1], entry[2]


CELL_RE = re.compile(r"^\$?([A-Z]{1,3})\$?([0-9]+)$")
COLUMN_RE = re.compile(r"^\$?([A-Z]{1,3})$")
ROW_RE = re.compile(r"^\$?([0-9]+)$")


def cell_location(text):
    """(row, column, row relative, column relative), 0-based, of `A1`, `$A$1`…"""
    m = CELL_RE.match(text.upper())
    if not m:
        raise Unsupported(f"reference {text}")
    col_rel = not text.startswith("$")
    row_rel = "$" not in text.lstrip("$")
    col, row = coordinate_from_string(text.replace("$", "").upper())
    return row - 1, column_index_from_string(col) - 1, row_rel, col_rel


def area_location(first, last):
    """(row1, col1, rr1, cr1), (row2, col2, rr2, cr2) of `A1:B2`, a whole column `A:B` or a
    whole row `1:2` (stored as all rows or all columns, that part absolute)."""
    if COLUMN_RE.match(first.upper()) and COLUMN_RE.match(last.upper()):
        c1 = column_index_from_string(first.lstrip("$").upper()) - 1
        c2 = column_index_from_string(last.lstrip("$").upper()) - 1
        return (0, c1, False, not first.startswith("$")), (LAST_ROW, c2, False, not last.startswith("$"))
    if ROW_RE.match(first) and ROW_RE.match(last):
        r1, r2 = int(first.lstrip("$")) - 1, int(last.lstrip("$")) - 1
        return (r1, 0, not first.startswith("$"), False), (r2, LAST_COL, not last.startswith("$"), False)
    return cell_location(first), cell_location(last)


def col_field(col, row_rel, col_rel):
    """ColRelShort ([MS-XLSB] 2.5.98.x): 14 bits of column, then fColRel and fRwRel."""
    return (col & 0x3FFF) | (0x4000 if col_rel else 0) | (0x8000 if row_rel else 0)


def split_sheet(text):
    """(sheet part or None, the reference) of `Sheet1!A1`, `'My Sheet'!A1`, `S1:S3!A1`."""
    if "!" not in text:
        return None, text
    sheet, ref = text.rsplit("!", 1)
    if sheet.startswith("'") and sheet.endswith("'"):
        sheet = sheet[1:-1].replace("''", "'")
    return sheet, ref


def relative_to(location, origin):
    """A shared formula's location: relative parts as offsets from `origin` (row, column)."""
    r, c, rr, cr = location
    if rr:
        r = (r - origin[0]) & 0xFFFFFFFF
    if cr:
        c = (c - origin[1]) & 0x3FFF
    return r, c, rr, cr


def reference_tokens(text, value_class, book, origin):
    """A cell, area, whole column or row, on this sheet or another (PtgRef3d/PtgArea3d);
    in a shared formula (`origin` set) relative parts are offsets (PtgRefN/PtgAreaN)."""
    shift = 0 if value_class else -0x20
    sheet, ref = split_sheet(text)
    parts = ref.split(":")
    if sheet is not None:
        if origin is not None:
            raise NotShareable("a reference to another sheet")
        first, _, last = sheet.partition(":")
        ixti = book.xti(first, last or first)
        if len(parts) == 1:
            r, c, rr, cr = cell_location(parts[0])
            return struct.pack("<BHIH", PTG_REF3D_V + shift, ixti, r, col_field(c, rr, cr))
        if len(parts) == 2:
            (r1, c1, rr1, cr1), (r2, c2, rr2, cr2) = area_location(*parts)
            return struct.pack(
                "<BHIIHH", PTG_AREA3D_V + shift, ixti, r1, r2, col_field(c1, rr1, cr1), col_field(c2, rr2, cr2)
            )
        raise Unsupported(f"reference {text}")
    if len(parts) == 1:
        location = cell_location(parts[0])
        ptg = PTG_REF_V
        if origin is not None:
            location, ptg = relative_to(location, origin), PTG_REFN_V
        r, c, rr, cr = location
        return struct.pack("<BIH", ptg + shift, r, col_field(c, rr, cr))
    if len(parts) == 2:
        first, last = area_location(*parts)
        ptg = PTG_AREA_V
        if origin is not None:
            first, last, ptg = relative_to(first, origin), relative_to(last, origin), PTG_AREAN_V
        (r1, c1, rr1, cr1), (r2, c2, rr2, cr2) = first, last
        return struct.pack("<BIIHH", ptg + shift, r1, r2, col_field(c1, rr1, cr1), col_field(c2, rr2, cr2))
    raise Unsupported(f"reference {text}")


def is_reference(text):
    """Whether an operand is a cell, area, whole column or row (perhaps on another sheet),
    not a defined name."""
    _, ref = split_sheet(text)
    parts = [p.upper() for p in ref.split(":")]
    if len(parts) == 1:
        return bool(CELL_RE.match(parts[0]))
    if len(parts) == 2:
        return any(all(pattern.match(p) for p in parts) for pattern in (CELL_RE, COLUMN_RE, ROW_RE))
    return False


def number_tokens(text):
    """PtgInt for a whole number that fits 16 bits as written, else PtgNum."""
    if text.isdigit() and int(text) <= 0xFFFF:
        return struct.pack("<BH", PTG_INT, int(text))
    return struct.pack("<Bd", PTG_NUM, float(text))


def string_tokens(text):
    if len(text) > 255:
        raise Unsupported("a string constant past 255 characters")
    data = text.encode("utf-16-le")
    return struct.pack("<BH", PTG_STR, len(data) // 2) + data


class Parser:
    """Recursive descent over openpyxl's tokens to Ptgs in reverse Polish order."""

    def __init__(self, formula, book, sheet, origin=None):
        self.book, self.sheet, self.origin = book, sheet, origin
        tokens = Tokenizer(formula).items
        if any(t.type == Token.WSPACE for t in tokens):
            # Spaces are only layout unless they are the intersection operator; drop the
            # ones between an operator and an operand, refuse the rest.
            kept = []
            for i, t in enumerate(tokens):
                if t.type != Token.WSPACE:
                    kept.append(t)
                    continue
                before = kept[-1] if kept else None
                after = tokens[i + 1] if i + 1 < len(tokens) else None
                if ends_operand(before) and starts_operand(after):
                    raise Unsupported("the intersection operator")
            tokens = kept
        self.tokens = tokens
        self.at = 0

    def peek(self):
        return self.tokens[self.at] if self.at < len(self.tokens) else None

    def take(self):
        token = self.peek()
        self.at += 1
        return token

    def parse(self):
        out = self.expression(0, True)
        if self.peek() is not None:
            raise Unsupported(f"unexpected {self.peek().value!r}")
        return out

    def expression(self, level, value_class):
        if level == len(BINARY):
            return self.unary(value_class)
        out = self.expression(level + 1, value_class)
        while True:
            t = self.peek()
            if t is None or t.type != Token.OP_IN or t.value not in BINARY[level]:
                return out
            self.take()
            out += self.expression(level + 1, True)
            out += bytes([BINARY[level][t.value]])

    def unary(self, value_class):
        t = self.peek()
        if t is not None and t.type == Token.OP_PRE:
            self.take()
            inner = self.unary(True)
            return inner + bytes([PTG_UMINUS if t.value == "-" else PTG_UPLUS])
        out = self.primary(value_class)
        while self.peek() is not None and self.peek().type == Token.OP_POST:
            self.take()
            out += bytes([PTG_PERCENT])
        return out

    def primary(self, value_class):
        t = self.take()
        if t is None:
            raise Unsupported("a formula that ends early")
        if t.type == Token.PAREN and t.subtype == Token.OPEN:
            inner = self.expression(0, value_class)
            close = self.take()
            if close is None or close.type != Token.PAREN:
                raise Unsupported("unbalanced parentheses")
            return inner + bytes([PTG_PAREN])
        if t.type == Token.FUNC and t.subtype == Token.OPEN:
            return self.call(t.value[:-1].upper())
        if t.type == Token.OPERAND:
            return self.operand(t, value_class)
        raise Unsupported(f"token {t.value!r}")

    def operand(self, t, value_class):
        if t.subtype == Token.NUMBER:
            return number_tokens(t.value)
        if t.subtype == Token.TEXT:
            return string_tokens(t.value[1:-1].replace('""', '"'))
        if t.subtype == Token.LOGICAL:
            return struct.pack("<BB", PTG_BOOL, 1 if t.value.upper() == "TRUE" else 0)
        if t.subtype == Token.ERROR:
            if t.value not in ERRORS:
                raise Unsupported(f"error {t.value}")
            return struct.pack("<BB", PTG_ERR, ERRORS[t.value])
        if t.subtype == Token.RANGE:
            if is_reference(t.value):
                return reference_tokens(t.value, value_class, self.book, self.origin)
            return self.name_tokens(t.value, value_class)
        raise Unsupported(f"operand {t.value!r}")

    def name_tokens(self, text, value_class):
        """PtgName of a defined name: the sheet's own, else the workbook's."""
        sheet, name = split_sheet(text)
        scope = self.book.sheet_index(sheet) if sheet is not None else self.sheet
        index = self.book.name_index(name, scope)
        shift = 0 if value_class else -0x20
        return struct.pack("<BI", PTG_NAME_V + shift, index)

    def call(self, name):
        future = name.startswith("_XLFN.")
        if name.startswith("_XL") and not future:
            raise Unsupported(f"function {name}")
        if future:
            # A function newer than the Ftab ([MS-XLSB] 2.5.98.10): a hidden future-function
            # name, pushed first, called through the user-defined function number.
            if "_XLWS." in name or "_XLPM." in name:
                raise Unsupported(f"function {name}")
            head = struct.pack("<BI", PTG_NAME_V - 0x20, self.book.future_function(name))
            iftab, least, most = USER_FUNCTION, 0, 254
        else:
            head = b""
            iftab, least, most = function_entry(name)
        args = []
        if self.peek() is not None and self.peek().type == Token.FUNC and self.peek().subtype == Token.CLOSE:
            self.take()
        else:
            while True:
                t = self.peek()
                if t is not None and (t.type == Token.SEP or (t.type == Token.FUNC and t.subtype == Token.CLOSE)):
                    args.append(bytes([PTG_MISSARG]))
                else:
                    args.append(self.expression(0, False))
                t = self.take()
                if t is None:
                    raise Unsupported("an unclosed function call")
                if t.type == Token.FUNC and t.subtype == Token.CLOSE:
                    break
                if t.type != Token.SEP or t.subtype != Token.ARG:
                    raise Unsupported(f"token {t.value!r} in {name}")
        if not least <= len(args) <= most:
            raise Unsupported(f"{name} with {len(args)} arguments")
        body = head + b"".join(args)
        if future:
            return body + struct.pack("<BBH", PTG_FUNCVAR_V, len(args) + 1, iftab)
        if least == most:
            return body + struct.pack("<BH", PTG_FUNC_V, iftab)
        return body + struct.pack("<BBH", PTG_FUNCVAR_V, len(args), iftab)


def ends_operand(t):
    return t is not None and (
        t.type == Token.OPERAND or (t.type in (Token.PAREN, Token.FUNC) and t.subtype == Token.CLOSE)
    )


def starts_operand(t):
    return t is not None and (
        t.type == Token.OPERAND or (t.type in (Token.PAREN, Token.FUNC) and t.subtype == Token.OPEN)
    )


def compile_formula(formula, book, sheet, origin=None):
    """The Ptgs of `formula` in sheet number `sheet`; with `origin` (row, column), as the
    formula a block of cells shares, its relative references offsets from the cell."""
    return Parser(formula, book, sheet, origin).parse()


class Book:
    """What formulas point at beyond their sheet: the sheets, the ExternSheet entries
    (XTI: this workbook's first and last sheet) and the defined names, in file order."""

    def __init__(self, sheets):
        self.sheets = sheets
        self.xtis = []
        # [name, sheet index or None, flags, rgce (None until compiled)]
        self.names = []

    def sheet_index(self, name):
        for i, s in enumerate(self.sheets):
            if s.upper() == name.upper():
                return i
        raise Unsupported(f"a reference to a sheet {name} the workbook lacks")

    def xti(self, first, last):
        entry = (self.sheet_index(first), self.sheet_index(last))
        if entry not in self.xtis:
            self.xtis.append(entry)
        return self.xtis.index(entry)

    def add_name(self, name, scope):
        self.names.append([name, scope, 0, None])

    def name_index(self, name, scope):
        """The 1-based index of PtgName: the name of sheet `scope`, else the workbook's."""
        for wanted in (scope, None):
            for i, (n, s, flags, _) in enumerate(self.names):
                if n.upper() == name.upper() and s == wanted and not flags & NAME_FUTURE:
                    return i + 1
        raise Unsupported(f"the name {name}")

    def future_function(self, name):
        """The 1-based index of the hidden name `_xlfn.NAME` a future function is called by."""
        spelled = "_xlfn." + name[len("_XLFN."):]
        for i, (n, _, flags, _) in enumerate(self.names):
            if flags & NAME_FUTURE and n.upper() == spelled.upper():
                return i + 1
        self.names.append([spelled, None, NAME_HIDDEN | NAME_FUNC | NAME_PROC | NAME_FUTURE, b""])
        return len(self.names)


# ---------------------------------------------------------------- the source workbook


ESCAPED = re.compile(r"_x([0-9A-Fa-f]{4})_")


def unescape(text):
    """An ST_Xstring's `_xHHHH_` escapes (ECMA-376 Part 1, 22.9.2.19) as the characters."""
    return ESCAPED.sub(lambda m: chr(int(m.group(1), 16)), text)


def source_values(path):
    """{sheet name: {(row, col): (type, text)}} of every cell's <v> as Excel saved it."""
    z = zipfile.ZipFile(path)
    shared = []
    if "xl/sharedStrings.xml" in z.namelist():
        for si in ET.fromstring(z.read("xl/sharedStrings.xml")).iter(MAIN_NS + "si"):
            shared.append(unescape("".join(t.text or "" for t in si.iter(MAIN_NS + "t"))))
    out = {}
    for name, root in sheet_roots(z):
        cells = {}
        for c in root.iter(MAIN_NS + "c"):
            t = c.get("t", "n")
            v = c.find(MAIN_NS + "v")
            if c.get("vm") is not None:
                # A rich value (an error such as #SPILL! stored as #VALUE! with metadata):
                # this writer cannot carry it, so the cell is left out.
                print(f"{path}: {c.get('r')} left out: a rich value", file=sys.stderr)
                continue
            if t == "inlineStr":
                text = unescape("".join(x.text or "" for x in c.iter(MAIN_NS + "t")))
                t = "str"
            elif v is None:
                continue
            else:
                text = v.text or ""
                if t == "s":
                    text, t = shared[int(text)], "str"
                elif t == "str":
                    text = unescape(text)
            col, row = coordinate_from_string(c.get("r"))
            cells[(row - 1, column_index_from_string(col) - 1)] = (t, text)
        out[name] = cells
    return out


def sheet_roots(z):
    """(name, parsed sheet part) of each sheet of the package `z`, in the workbook's order."""
    rels = {r.get("Id"): r.get("Target") for r in ET.fromstring(z.read("xl/_rels/workbook.xml.rels"))}
    for sheet in ET.fromstring(z.read("xl/workbook.xml")).iter(MAIN_NS + "sheet"):
        target = rels[sheet.get(REL_NS + "id")].lstrip("/")
        part = target if target.startswith("xl/") else "xl/" + target
        yield sheet.get("name"), ET.fromstring(z.read(part))


# ---------------------------------------------------------------- records


def record(rtype, body=b""):
    """A record: its type and size as [MS-XLSB] 2.1.4 variable-length integers."""
    head = bytearray()
    for value, most in ((rtype, 2), (len(body), 4)):
        for _ in range(most):
            byte = value & 0x7F
            value >>= 7
            head.append(byte | (0x80 if value else 0))
            if not value:
                break
    return bytes(head) + body


def wide(text):
    """XLWideString: a count of UTF-16 code units, then the units."""
    data = text.encode("utf-16-le")
    return struct.pack("<I", len(data) // 2) + data


def cell_head(col):
    """Cell ([MS-XLSB] 2.5.10): the column, then iStyleRef 0 (the General format)."""
    return struct.pack("<II", col, 0)


def formula_body(rgce, extra=b""):
    """GrbitFmla (no flags), then CellParsedFormula: cce, rgce, cb, rgcb (the extra data)."""
    return struct.pack("<HI", 0, len(rgce)) + rgce + struct.pack("<I", len(extra)) + extra


class Strings:
    def __init__(self):
        self.index, self.items, self.uses = {}, [], 0

    def add(self, text):
        self.uses += 1
        if text not in self.index:
            self.index[text] = len(self.items)
            self.items.append(text)
        return self.index[text]

    def part(self):
        body = record(0x9F, struct.pack("<II", self.uses, len(self.items)))  # BrtBeginSst
        for text in self.items:
            body += record(0x13, b"\x00" + wide(text))  # BrtSSTItem: RichStr, no runs
        return body + record(0xA0)  # BrtEndSst


def value_cell(col, kind, text, strings):
    if kind == "n":
        return record(0x05, cell_head(col) + struct.pack("<d", float(text)))  # BrtCellReal
    if kind == "b":
        return record(0x04, cell_head(col) + bytes([text == "1"]))  # BrtCellBool
    if kind == "e":
        return record(0x03, cell_head(col) + bytes([ERRORS[text]]))  # BrtCellError
    return record(0x07, cell_head(col) + struct.pack("<I", strings.add(text)))  # BrtCellIsst


def formula_cell(col, kind, text, rgce, extra=b""):
    body = formula_body(rgce, extra)
    if kind == "n":
        return record(0x09, cell_head(col) + struct.pack("<d", float(text)) + body)
    if kind == "b":
        return record(0x0A, cell_head(col) + bytes([text == "1"]) + body)
    if kind == "e":
        return record(0x0B, cell_head(col) + bytes([ERRORS[text]]) + body)
    return record(0x08, cell_head(col) + wide(text) + body)


def shared_member_rgce(anchor):
    """A cell of a shared formula: PtgExp naming the anchor's row, and in the extra data the
    PtgExtraCol naming its column ([MS-XLSB] 2.5.98.40)."""
    return struct.pack("<BI", PTG_EXP, anchor[0]), struct.pack("<I", anchor[1])


def array_formula_record(area, rgce):
    """BrtArrFmla ([MS-XLSB] 2.4.6): the cells' RfX, a flags byte (fAlwaysCalc 0), then the
    formula."""
    (r1, c1), (r2, c2) = area
    head = struct.pack("<IIIIB", r1, r2, c1, c2, 0)
    return record(0x1AA, head + struct.pack("<I", len(rgce)) + rgce + struct.pack("<I", 0))


def shared_formula_record(area, rgce):
    """BrtShrFmla ([MS-XLSB] 2.4.785): the cells' RfX (rows, then columns), then the formula."""
    (r1, c1), (r2, c2) = area
    return record(0x1AB, struct.pack("<IIII", r1, r2, c1, c2) + struct.pack("<I", len(rgce)) + rgce + struct.pack("<I", 0))


def sheet_part(cells):
    """cells: {(row, col): record bytes}."""
    by_row = {}
    for r, c in cells:
        by_row.setdefault(r, []).append(c)
    rows = sorted(by_row)
    cols = sorted({c for _, c in cells})
    dim = (rows[0], rows[-1], cols[0], cols[-1]) if cells else (0, 0, 0, 0)
    body = record(0x81)  # BrtBeginSheet
    body += record(0x94, struct.pack("<IIII", *dim))  # BrtWsDim
    body += record(0x91)  # BrtBeginSheetData
    for row in rows:
        in_row = sorted(by_row[row])
        # BrtRowHdr: rw, ixfe, miyRw (15 pt), three flag bytes, one BrtColspan.
        body += record(0x00, struct.pack("<IIHBBBIII", row, 0, 300, 0, 0, 0, 1, in_row[0], in_row[-1]))
        for col in in_row:
            body += cells[(row, col)]
    body += record(0x92)  # BrtEndSheetData
    return body + record(0x82)  # BrtEndSheet


def styles_part():
    """One cell format, General: the cell style XF and the cell XF every cell names."""
    # BrtXF: ixfeParent, iFmt 0 (General), iFont, iFill, ixBorder, trot, indent, two flag words.
    style_xf = record(0x2F, struct.pack("<HHHHHBBHH", 0xFFFF, 0, 0, 0, 0, 0, 0, 0, 0))
    cell_xf = record(0x2F, struct.pack("<HHHHHBBHH", 0, 0, 0, 0, 0, 0, 0, 0, 0))
    body = record(0x116)  # BrtBeginStyleSheet
    body += record(0x272, struct.pack("<I", 1)) + style_xf + record(0x273)  # cell style XFs
    body += record(0x269, struct.pack("<I", 1)) + cell_xf + record(0x26A)  # cell XFs
    return body + record(0x117)  # BrtEndStyleSheet


def workbook_part(names, date_1904, book):
    body = record(0x83)  # BrtBeginBook
    body += record(0x99, struct.pack("<II", 1 if date_1904 else 0, 0) + wide(""))  # BrtWbProp
    body += record(0x8F)  # BrtBeginBundleShs
    for i, name in enumerate(names):
        # BrtBundleSh: hsState visible, iTabID, strRelID, strName.
        body += record(0x9C, struct.pack("<II", 0, i + 1) + wide(f"rId{i + 1}") + wide(name))
    body += record(0x90)  # BrtEndBundleShs
    if book.xtis:
        # EXTERNALS: this workbook as supporting book 0, then the XTIs of the 3-D references.
        body += record(0x161) + record(0x165)  # BrtBeginExternals, BrtSupSelf
        xtis = b"".join(struct.pack("<Iii", 0, first, last) for first, last in book.xtis)
        body += record(0x16A, struct.pack("<I", len(book.xtis)) + xtis)  # BrtExternSheet
        body += record(0x162)  # BrtEndExternals
    for name, scope, flags, rgce in book.names:
        # BrtName: flags, chKey, itab (0xFFFFFFFF: the workbook's), name, NameParsedFormula
        # (cce, rgce, cb 0), a null comment; a macro's name (fProc) four more null strings.
        itab = 0xFFFFFFFF if scope is None else scope
        text = struct.pack("<IBI", flags, 0, itab) + wide(name) + struct.pack("<I", len(rgce)) + rgce
        text += struct.pack("<I", 0) + struct.pack("<I", 0xFFFFFFFF) * (5 if flags & NAME_PROC else 1)
        body += record(0x27, text)
    return body + record(0x84)  # BrtEndBook


def package(names, sheets, strings, date_1904, book):
    ct = (
        '<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n'
        '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
        '<Default Extension="bin" ContentType="application/vnd.ms-excel.sheet.binary.macroEnabled.main"/>'
        '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
        '<Default Extension="xml" ContentType="application/xml"/>'
        '<Override PartName="/xl/workbook.bin" ContentType="application/vnd.ms-excel.sheet.binary.macroEnabled.main"/>'
        '<Override PartName="/docProps/app.xml" ContentType="application/vnd.openxmlformats-officedocument.extended-properties+xml"/>'
    )
    for i in range(len(names)):
        ct += (
            f'<Override PartName="/xl/worksheets/sheet{i + 1}.bin" '
            'ContentType="application/vnd.ms-excel.worksheet"/>'
        )
    ct += (
        '<Override PartName="/xl/sharedStrings.bin" ContentType="application/vnd.ms-excel.sharedStrings"/>'
        '<Override PartName="/xl/styles.bin" ContentType="application/vnd.ms-excel.styles"/></Types>'
    )
    rels = (
        '<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n'
        '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
        '<Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.bin"/>'
        '<Relationship Id="rId2" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/extended-properties" Target="docProps/app.xml"/>'
        "</Relationships>"
    )
    wb_rels = (
        '<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n'
        '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
    )
    for i in range(len(names)):
        wb_rels += (
            f'<Relationship Id="rId{i + 1}" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/worksheet" '
            f'Target="worksheets/sheet{i + 1}.bin"/>'
        )
    wb_rels += (
        f'<Relationship Id="rId{len(names) + 1}" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/sharedStrings" '
        'Target="sharedStrings.bin"/>'
        f'<Relationship Id="rId{len(names) + 2}" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/styles" '
        'Target="styles.bin"/></Relationships>'
    )
    app = (
        '<?xml version="1.0" encoding="UTF-8" standalone="yes"?>\n'
        '<Properties xmlns="http://schemas.openxmlformats.org/officeDocument/2006/extended-properties">'
        "<Application>tests/data/xlsb/make_xlsb.py</Application></Properties>"
    )
    parts = [
        ("[Content_Types].xml", ct.encode()),
        ("_rels/.rels", rels.encode()),
        ("docProps/app.xml", app.encode()),
        ("xl/workbook.bin", workbook_part(names, date_1904, book)),
        ("xl/_rels/workbook.bin.rels", wb_rels.encode()),
    ]
    parts += [(f"xl/worksheets/sheet{i + 1}.bin", sheet_part(s)) for i, s in enumerate(sheets)]
    parts.append(("xl/sharedStrings.bin", strings.part()))
    parts.append(("xl/styles.bin", styles_part()))
    return parts


def source_shared(path):
    """{sheet name: {(row, col): (group, anchor's area or None, anchor's formula)}} of the
    cells of shared formulas (`<f t="shared" si=…>`), from the sheet parts."""
    out = {}
    for name, root in sheet_roots(zipfile.ZipFile(path)):
        cells = {}
        for c in root.iter(MAIN_NS + "c"):
            f = c.find(MAIN_NS + "f")
            if f is None or f.get("t") != "shared":
                continue
            col, row = coordinate_from_string(c.get("r"))
            area = None
            if f.get("ref"):
                first, _, last = f.get("ref").partition(":")
                (r1, c1, _, _), (r2, c2, _, _) = cell_location(first), cell_location(last or first)
                area = ((r1, c1), (r2, c2))
            cells[(row - 1, column_index_from_string(col) - 1)] = (f.get("si"), area, f.text)
        out[name] = cells
    return out


def defined_names(book_xl):
    """(name, sheet index or None, formula) of the source's defined names, built-in ones
    (print areas…) left out."""
    found = [(name, None, d.attr_text) for name, d in book_xl.defined_names.items()]
    for i, ws in enumerate(book_xl.worksheets):
        found += [(name, i, d.attr_text) for name, d in ws.defined_names.items()]
    return [n for n in found if not n[0].startswith("_xlnm.")]


def compile_names(book, found, skipped):
    """Puts the defined names in `book` with their formulas; a name whose formula does not
    compile is left out (and the formulas using it are written as their values)."""
    while True:
        book.names, book.xtis = [], []
        for name, scope, _ in found:
            book.add_name(name, scope)
        failed = None
        for i, (name, scope, formula) in enumerate(found):
            try:
                parser = Parser("=" + formula, book, scope)
                rgce = parser.expression(0, False)
                if parser.peek() is not None:
                    raise Unsupported(f"unexpected {parser.peek().value!r}")
                book.names[i][3] = rgce
            except Unsupported as why:
                failed = i
                skipped.append(("(names)", name, str(why)))
                break
        if failed is None:
            return
        found = found[:failed] + found[failed + 1 :]


def shared_groups(book, sheet, shared, cached, skipped):
    """{group: (anchor, area, rgce)} of the shared formulas of a sheet that compile as one;
    the others are written cell by cell."""
    groups = {}
    for pos, (group, area, text) in shared.items():
        if area is None or pos not in cached or text is None:
            continue
        try:
            groups[group] = (pos, area, compile_formula(text, book, sheet, origin=pos))
        except Unsupported as why:
            if not isinstance(why, NotShareable):
                continue
    return groups


def array_formulas(ws, book, sheet, skipped):
    """{cell: (anchor, area, rgce)} of every cell of the sheet's array formulas that compile
    (a legacy Ctrl+Shift+Enter array, or a dynamic array over the cells it spilled to)."""
    cells = {}
    for row in ws.iter_rows():
        for cell in row:
            if not isinstance(cell.value, ArrayFormula):
                continue
            first, _, last = (cell.value.ref or cell.coordinate).partition(":")
            (r1, c1, _, _), (r2, c2, _, _) = cell_location(first), cell_location(last or first)
            try:
                rgce = compile_formula(cell.value.text, book, sheet)
            except Unsupported as why:
                skipped.append((ws.title, cell.coordinate, f"an array formula with {why}"))
                continue
            anchor = (r1, c1)
            for r in range(r1, r2 + 1):
                for c in range(c1, c2 + 1):
                    cells[(r, c)] = (anchor, ((r1, c1), (r2, c2)), rgce)
    return cells


def convert(source, out, listing):
    values = source_values(source)
    shared_cells = source_shared(source)
    book_xl = load_workbook(source, data_only=False)
    strings = Strings()
    names, sheets, written, skipped = [], [], [], []
    book = Book([ws.title for ws in book_xl.worksheets])
    compile_names(book, defined_names(book_xl), skipped)
    for index, ws in enumerate(book_xl.worksheets):
        names.append(ws.title)
        cells = {}
        cached = values.get(ws.title, {})
        shared = shared_cells.get(ws.title, {})
        groups = shared_groups(book, index, shared, cached, skipped)
        arrays = array_formulas(ws, book, index, skipped)
        for row in ws.iter_rows():
            for cell in row:
                pos = (cell.row - 1, cell.column - 1)
                formula = cell.value if cell.data_type == "f" else None
                if pos not in cached:
                    if formula is not None:
                        skipped.append((ws.title, cell.coordinate, "no cached value"))
                    continue
                kind, text = cached[pos]
                kind = "str" if kind in ("s", "str") else kind
                if pos in arrays:
                    anchor, area, array_rgce = arrays[pos]
                    rgce, extra = shared_member_rgce(anchor)
                    cells[pos] = formula_cell(pos[1], kind, text, rgce, extra)
                    if pos == anchor:
                        cells[pos] += array_formula_record(area, array_rgce)
                        # The first cell is listed: its formula computes the array.
                        written.append((ws.title, cell.coordinate, "{" + formula.text + "}"))
                    continue
                if isinstance(formula, (ArrayFormula, DataTableFormula)):
                    skipped.append((ws.title, cell.coordinate, "an array formula or data table"))
                    formula = None
                group = groups.get(shared[pos][0]) if pos in shared else None
                if isinstance(formula, str) and group is not None:
                    anchor, area, shared_rgce = group
                    rgce, extra = shared_member_rgce(anchor)
                    cells[pos] = formula_cell(pos[1], kind, text, rgce, extra)
                    if pos == anchor:
                        cells[pos] += shared_formula_record(area, shared_rgce)
                    written.append((ws.title, cell.coordinate, formula))
                    continue
                if isinstance(formula, str):
                    try:
                        rgce = compile_formula(formula, book, index)
                        cells[pos] = formula_cell(pos[1], kind, text, rgce)
                        written.append((ws.title, cell.coordinate, formula))
                        continue
                    except Unsupported as why:
                        skipped.append((ws.title, cell.coordinate, str(why)))
                cells[pos] = value_cell(pos[1], kind, text, strings)
        sheets.append(cells)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in package(names, sheets, strings, book_xl.epoch.year == 1904, book):
            info = zipfile.ZipInfo(name, date_time=(2026, 11, 28, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
    with open(listing, "w", encoding="utf-8") as f:
        for sheet, cell, formula in written:
            # The formula column is for people: its tabs and line breaks become spaces.
            f.write(f"{sheet}\t{cell}\t{' '.join(formula.split())}\n")
    for sheet, cell, why in skipped:
        print(f"{source}: {sheet}!{cell} kept as its value: {why}", file=sys.stderr)
    print(f"{source}: {len(written)} formulas written, {len(skipped)} kept as values", file=sys.stderr)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    convert(*sys.argv[1:])
