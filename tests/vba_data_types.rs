//! VBA's data types as values carry them through a program: a Date keeps its type through
//! parameters, arrays, Collections and Dictionaries and shows as a date wherever it becomes
//! a String; LongLong is VBA7's 64-bit integer. Expected values are MS-VBAL's and the Office
//! VBA language reference's (each test cites its sections), not our own output.

mod common;

use common::vba::{printed_after as printed, run_module as run};

// "Type conversion functions", CStr: "Date: A String containing a date in the short date
// format of your system" (en-US: m/d/yyyy, the time as h:mm:ss AM/PM, only the part that is
// there, "Print # statement"; a time alone on day 0, midnight of day 0 as 12:00:00 AM).
// "Format function": a value without a format is shown as "General Date" shows a Date, and
// the "General Date" named format is the same text; a format given is used as given. "Str
// function" makes a number's String; a Date's is its date text (no sign's space). Values
// that are no Dates are converted as numbers, as before.
#[test]
fn cstr_format_and_str_of_a_date_show_the_date() {
    let out = printed(
        "",
        "    Dim d As Date, t As Date, s As String\n    d = #1/2/2024#\n    t = #12:30:00 PM#\n\
         \x20   Debug.Print CStr(d); \"|\"; Format(d); \"|\"; Str(d); \"|\"; Format$(d + t, \"General Date\")\n\
         \x20   Debug.Print CStr(t); \"|\"; CStr(d + t); \"|\"; CStr(#12:00:00 AM#); \"|\"; Format(d, \"yyyy-mm-dd\")\n\
         \x20   s = CStr(d + 1)\n    Debug.Print s; \"|\"; CStr(45293); \"|\"; Str(5); \"|\"; Format(45293)",
    );
    assert_eq!(
        out,
        [
            "1/2/2024|1/2/2024|1/2/2024|1/2/2024 12:30:00 PM",
            "12:30:00 PM|1/2/2024 12:30:00 PM|12:00:00 AM|2024-01-02",
            "1/3/2024|45293| 5|45293",
        ]
    );
}

// "LongLong data type": a signed 64-bit integer, -9,223,372,036,854,775,808 to
// 9,223,372,036,854,775,807, type-declaration character `^`; [MS-VBAL] 3.3.2, Number
// Tokens: `5^` is an INTEGER whose declared type is LongLong; "VarType function": vbLongLong
// is 20; 5.6.9.3, arithmetic on LongLong operands is LongLong, and a result past its range is
// Overflow ("Overflow (Error 6)"), as is assigning one to a LongLong. `2^3` stays the
// exponent, a Double ([MS-VBAL] 5.6.9.3.8), as `10^-3` (a `^` before a sign or an operand).
#[test]
fn longlong_is_a_64_bit_integer_type() {
    let out = printed(
        "",
        "    Dim x As LongLong, y As LongLong\n    x = 5^\n\
         \x20   Debug.Print TypeName(x); VarType(x); TypeName(5^); TypeName(2^3); 2^3; 7^ * 2\n\
         \x20   x = 4611686018427387904^\n    y = -x * 2\n    Debug.Print y = -2 * 4611686018427387904#; TypeName(x + 1)\n\
         \x20   On Error Resume Next\n    y = x * 2\n    Debug.Print Err.Number\n    Err.Clear\n\
         \x20   y = 9.3E+18\n    Debug.Print Err.Number\n    Err.Clear\n    y = -9.3E+18\n    Debug.Print Err.Number\n\
         \x20   Err.Clear\n    y = CLngLng(-9.3E+18)\n    Debug.Print Err.Number",
    );
    assert_eq!(out, ["LongLong 20 LongLongDouble 8  14 ", "TrueLongLong", " 6 ", " 6 ", " 6 ", " 6 "]);
    // A LongLong literal past the type is a compile error naming its place.
    let e = run("Sub Main()\n    x = 9300000000000000000^\nEnd Sub\n").unwrap_err();
    assert!(e.message.contains("LongLong"), "{e}");
    assert_eq!(e.span.unwrap().line, 2, "{e}");
}

// [MS-VBAL] 2.1.1.1 and "VarType function": a Variant holds a Date as a Date (TypeName
// "Date", VarType 7, vbDate) wherever the value goes: 5.3.1.11, a Variant parameter, ByVal
// or ByRef, is bound to the argument's value with its type, and a ByRef one gives back what
// the procedure made of it; 5.3.1.2, a Function's result is what its name was assigned;
// "Using arrays", an item of a Variant array, kept by ReDim Preserve; "Collection object"
// and "Dictionary object", an item as added or assigned. `d + 1` is a Date (5.6.9.3.3). Shown
// as text, each is the date (as Debug.Print shows a Date); a number among them stays a number
// (a Double: 5.5, as the Variants here do not tell a whole number's Integer from a Double).
#[test]
fn a_date_keeps_its_type_through_parameters_results_arrays_and_collections() {
    let module = "Function Id(x)\n    Id = x\nEnd Function\n\
                  Sub Show(ByVal x, ByRef y, z As Date)\n    Debug.Print TypeName(x); VarType(y); TypeName(z); \" \"; x\nEnd Sub\n\
                  Sub Later(ByRef x)\n    x = x + 1\nEnd Sub\n";
    let out = printed(
        module,
        "    Dim d As Date, a(2) As Date, v(2), c As New Collection, dic, w\n    d = #1/2/2024#\n\
         \x20   Show d, d, d\n    Debug.Print TypeName(Id(d)); VarType(Id(d)); \" \"; Id(d); \" \"; TypeName(Id(5.5))\n\
         \x20   a(1) = d: v(0) = d: v(1) = 5.5\n    ReDim Preserve v(3)\n\
         \x20   Debug.Print TypeName(a(1)); VarType(a(1)); TypeName(v(0)); VarType(v(0)); TypeName(v(1)); \" \"; CStr(v(0))\n\
         \x20   c.Add d: c.Add 7.5, \"k\": c.Add d + 1, Before:=1\n\
         \x20   Debug.Print TypeName(c(1)); TypeName(c(2)); TypeName(c(\"k\")); VarType(c.Item(2)); \" \"; c(1)\n\
         \x20   Set dic = CreateObject(\"Scripting.Dictionary\")\n    dic.Add \"k\", d\n    dic(\"j\") = d + 2\n    dic(\"n\") = 3.5\n\
         \x20   Debug.Print TypeName(dic(\"k\")); VarType(dic.Item(\"j\")); TypeName(dic(\"n\")); \" \"; dic(\"j\")\n\
         \x20   w = d\n    Later w\n    Debug.Print TypeName(w); \" \"; w; \" \"; \"on \" & Id(d)\n\
         \x20   w = v(0)\n    Debug.Print TypeName(w); VarType(d + 1)\n\
         \x20   w = Array(d, 2.5, d + 1)\n    Debug.Print TypeName(w(0)); TypeName(w(1)); TypeName(w(2)); \" \"; w(2)",
    );
    assert_eq!(
        out,
        [
            "Date 7 Date 1/2/2024",
            "Date 7  1/2/2024 Double",
            "Date 7 Date 7 Double 1/2/2024",
            "DateDateDouble 7  1/3/2024",
            "Date 7 Double 1/4/2024",
            "Date 1/3/2024 on 1/2/2024",
            "Date 7 ",
            "DateDoubleDate 1/3/2024",
        ]
    );
}

// [MS-VBAL] 3.3.5.3 "Special Identifier Forms" and the language reference's "Type
// characters" table: a name declared with a type character has that type (`%` Integer, `&`
// Long, `@` Currency, `!` Single, `#` Double, `$` String), in Dim, ReDim, Const, parameters
// and a Function's name; the name is used without it. An Integer rounds what it is given
// half to even ("Type conversion functions", CInt).
#[test]
fn names_declared_with_a_type_character_have_its_type() {
    let module = "Function Half#(ByVal x%)\n    Half = x / 2\nEnd Function\n";
    let out = printed(
        module,
        "    Dim I%, N&, C@, F!, X#, S$, h#()\n    Const K# = 2\n\
         \x20   I = 2.5: N = 70000: X = 1 / 4: S = 12\n\
         \x20   Debug.Print TypeName(I); TypeName(N); TypeName(C); TypeName(F); TypeName(X); TypeName(S); TypeName(K)\n\
         \x20   ReDim h(1 To 2)\n    h(1) = \"2.5\"\n\
         \x20   Debug.Print I; N; X; S; h(1); TypeName(h(1)); Half(2.6); TypeName(Half(1))",
    );
    assert_eq!(out, ["IntegerLongCurrencySingleDoubleStringDouble", " 2  70000  0.25 12 2.5 Double 1.5 Double"]);
}

// The language reference's "Using arrays" ("Assigning arrays"): a dynamic array of a declared
// type takes a whole array of that type (`a = Squares(3)`, `s = Split(…)`), with its bounds;
// a Function declared `As Double()` returns one ([MS-VBAL] 5.3.1.2, function-declaration's
// array return type). An array passed ByRef to a Variant parameter is the caller's array:
// what the procedure stores in it stays ([MS-VBAL] 5.3.1.11). A dynamic array before its
// first ReDim has no bounds: UBound is run-time error 9, "Subscript out of range".
#[test]
fn an_array_variable_of_a_declared_type_takes_a_whole_array() {
    let module = "Function Squares(n) As Double()\n    Dim r() As Double, i\n    ReDim r(1 To n)\n\
                  \x20   For i = 1 To n: r(i) = i * i: Next\n    Squares = r\nEnd Function\n\
                  Sub Fill(v)\n    v(2) = 7\nEnd Sub\n";
    let out = printed(
        module,
        "    Dim a() As Double, b(1 To 3) As Double, s() As String, c() As Long, u\n\
         \x20   a = Squares(3)\n    Debug.Print LBound(a); UBound(a); a(3); TypeName(a(3))\n\
         \x20   Fill b\n    Debug.Print b(2)\n\
         \x20   s = Split(\"x,y\", \",\")\n    Debug.Print UBound(s); s(1)\n\
         \x20   On Error Resume Next\n    u = UBound(c)\n    Debug.Print Err.Number",
    );
    assert_eq!(out, [" 1  3  9 Double", " 7 ", " 1 y", " 9 "]);
}

// [MS-VBAL] 5.3.1.5 (function-declaration): a Function's value is what its name holds when
// it returns; an array keeps its bounds and its one item ("Using arrays": arrays are
// declared with the bounds they have, not rebased). Excel gives VBA a worksheet function's
// one-row array as a one-dimensional array from 1, whatever the module's Option Base
// ("WorksheetFunction.Transpose": a column made a row; `Application.Transpose` of a
// column is the idiom that reads it into a 1-based list).
#[test]
fn a_function_returns_its_array_with_its_bounds() {
    let module = "Option Base 0\nFunction Limits()\n    Dim t(1 To 2) As Double\n    t(1) = 10: t(2) = 20\n\
                  \x20   Limits = t\nEnd Function\nFunction One()\n    Dim t(5 To 5)\n    t(5) = \"x\"\n    One = t\nEnd Function\n";
    let out = printed(
        module,
        "    Dim v, w\n    v = Limits()\n    Debug.Print LBound(v); UBound(v); v(2)\n\
         \x20   w = One()\n    Debug.Print IsArray(w); LBound(w); w(5)\n\
         \x20   [A1] = 1: [A2] = 2: [A3] = 3\n    w = Application.Transpose(Range(\"A1:A3\"))\n\
         \x20   Debug.Print LBound(w); UBound(w); w(3)",
    );
    assert_eq!(out, [" 1  2  20 ", "True 5 x", " 1  3  3 "]);
}

// [MS-VBAL] 5.3.1.11: an argument that is a variable holding an object passes the object;
// a procedure given a Worksheet (`Sub WriteRow(ws As Worksheet, …)`) writes its cells.
#[test]
fn a_worksheet_passes_as_an_argument() {
    let module = "Sub Put2(ws As Worksheet, r As Long, v)\n    ws.Cells(r, 2).Value = v\nEnd Sub\n";
    let out = printed(
        module,
        "    Dim sh As Worksheet\n    Set sh = ActiveSheet\n    Put2 sh, 3, \"z\"\n    Debug.Print Range(\"B3\").Value",
    );
    assert_eq!(out, ["z"]);
}

// "UBound function" and "LBound function" take the array, whatever gives it: "Split
// function" returns "a zero-based, one-dimensional array", so `UBound(Split("a,b,c", ","))`
// is 2; a Function's array keeps the bounds it was given, and a Collection's item the bounds
// it was added with.
#[test]
fn ubound_and_lbound_of_an_array_an_expression_gives() {
    let module = "Function Pair()\n    Dim t(3 To 4)\n    Pair = t\nEnd Function\n";
    let out = printed(
        module,
        "    Dim c As New Collection\n    c.Add Array(4, 5, 6)\n\
         \x20   Debug.Print UBound(Split(\"a,b,c\", \",\")); LBound(Pair()); UBound(Pair()); UBound(c(1))",
    );
    assert_eq!(out, [" 2  3  4  2 "]);
}

// [MS-VBAL] 2.2 "Arrays" and 5.6.13.1 "Index Expressions": an array value carries the lower
// and upper bound of each dimension, so an array stored as an item of a Variant array
// (`A(2) = C` with `ReDim C(1 To n)`) keeps 1 To n through `A(2)(i)`, `UBound(A(2))`, a copy
// `X = A(2)`, an argument `F(A(2))`, a Function's result, and `ReDim Preserve` of the outer
// array; an item given a value afterwards is that value. Under Option Base 0 a lost bound
// would show as 0 To 3 (the spline module ModApproximate read its coefficients one off).
#[test]
fn an_array_stored_as_an_item_keeps_its_bounds() {
    let module = "Option Base 0\nFunction Pack()\n    Dim Out(1 To 2), B(1 To 3)\n    B(3) = 30\n    Out(1) = B\n\
                  \x20   Pack = Out\nEnd Function\nFunction Fourth(v)\n    Fourth = v(4)\nEnd Function\n\
                  Function Inner()\n    Dim A(1 To 2), C()\n    ReDim C(2 To 4)\n    C(4) = 44\n    A(2) = C\n\
                  \x20   Inner = A(2)\nEnd Function\n";
    let out = printed(
        module,
        "    Dim A(1 To 3) As Variant, C(), X, P, n\n    n = 4\n    ReDim C(1 To n)\n    C(4) = 4\n    A(2) = C\n\
         \x20   Debug.Print LBound(A(2)); UBound(A(2)); A(2)(4)\n\
         \x20   X = A(2)\n    Debug.Print LBound(X); UBound(X); X(4); Fourth(A(2))\n\
         \x20   P = Pack()\n    Debug.Print LBound(P(1)); UBound(P(1)); P(1)(3)\n\
         \x20   X = Inner()\n    Debug.Print LBound(X); UBound(X); X(4)\n\
         \x20   ReDim Preserve A(1 To 4)\n    Debug.Print UBound(A(2))\n\
         \x20   A(2) = 7\n    Debug.Print IsArray(A(2)); A(2)",
    );
    assert_eq!(out, [" 1  4  4 ", " 1  4  4  4 ", " 1  3  30 ", " 2  4  44 ", " 4 ", "False 7 "]);
}

// [MS-VBAL] 5.3.1.11 "Evaluation of Procedure Invocation Argument Lists": an argument that
// is an array's item (a variable) passed to a ByRef parameter is passed by reference, so
// what the procedure leaves in the parameter is the item's afterwards — a number, or an
// array item's own array changed inside (with its bounds, 2.2); a ByVal one is a copy.
#[test]
fn an_array_item_passed_by_reference_gets_what_the_procedure_left() {
    let module = "Sub Inc(x)\n    x = x + 1\nEnd Sub\nSub NoInc(ByVal x)\n    x = x + 1\nEnd Sub\n\
                  Sub Fill(v)\n    v(2) = 9\nEnd Sub\n";
    let out = printed(
        module,
        "    Dim A(1 To 3), C(1 To 2)\n    A(3) = 5\n    Inc A(3)\n    NoInc A(3)\n    A(1) = C\n    Fill A(1)\n\
         \x20   Debug.Print A(3); A(1)(2); LBound(A(1)); UBound(A(1))",
    );
    assert_eq!(out, [" 6  9  1  2 "]);
}

// [MS-VBAL] 3.3.5.3: `Function Greet$(n$)` declares Greet, a String Function; `Greet$(…)` and
// `Greet(…)` both call it, and `Greet = …` in its body sets its result.
#[test]
fn a_function_declared_with_dollar_is_called_with_or_without_it() {
    let module = "Function Greet$(n$)\n    Greet = \"hi \" & n\nEnd Function\n";
    let out = printed(module, "    Debug.Print Greet(\"a\"); \"|\"; Greet$(\"b\"); \"|\"; TypeName(Greet(\"c\"))");
    assert_eq!(out, ["hi a|hi b|String"]);
}

// [MS-VBAL] 5.6.9.3 "Arithmetic Operators": each operation's value type comes from its
// operands' value types, so an operation inside an expression has its type before the one
// around it is computed. "Variant data type": a Variant's Byte, Integer or Long result past
// its type's range "is promoted within the Variant to the next larger data type" (Byte to
// Integer, Integer to Long, Long to Double), where it is computed: `x * x - 30000` of the
// Integer 200 is the Long 40000 less an Integer, a Long; `(l + 1) - 1` of the Long
// 2,147,483,647 a Double; `-z - 1` of the Integer -32,768 the Long 32,768 less one. A declared
// Integer or Long operand still overflows at that operation, whatever the target's type
// ("Overflow (Error 6)").
#[test]
fn a_variant_operation_widens_where_it_is_computed() {
    let out = printed(
        "",
        "    Dim x, l, z, b, t As Byte, y\n    x = 200: l = 2147483647: z = -32768: t = 200: b = t\n\
         \x20   y = x * x - 30000\n    Debug.Print TypeName(y); y; TypeName(x * x - 30000); TypeName((x * x) \\ 2)\n\
         \x20   Debug.Print TypeName((l + 1) - 1); (l + 1) - 1; TypeName(-z - 1); -z - 1; TypeName((b + b) - b)\n\
         \x20   For i = 1 To 2
        If i = 1 Then x = 200 Else x = 2
        Debug.Print TypeName(x * x - 3); \" \";
    Next
         \x20   Debug.Print TypeName(x * 2.5 * 2)",
    );
    // The same operation computed again takes its new operands' types (the Integer 4 less 3).
    assert_eq!(out, ["Long 10000 LongLong", "Double 2147483647 Long 32767 Integer", "Long Integer Double"]);
    let overflow = |body: &str| {
        let src = format!("Sub Main()\n    Dim a As Integer, l As Long, d As Double, v\n{body}\nEnd Sub\n");
        let e = run(&src).unwrap_err();
        assert!(e.message.contains("Overflow (run-time error 6)"), "{body}: {e}");
    };
    overflow("    a = 200: v = a * a - 39999");
    overflow("    a = 200: d = a * a");
    overflow("    l = 65536: d = l * l - 1");
}

// "Single data type": a 32-bit (4-byte) floating-point number, ±3.402823E38, type character
// `!`; [MS-VBAL] 5.6.9.3: a Single operated with a Single, Byte, Boolean or Integer gives a
// Single (with a Long or a Double a Double), so each such operation's result is a Single:
// 2^24 + 1 is no Single and comes back 2^24. "Type conversion functions": CSng rounds to a
// Single, CDbl of it gives the Single's exact value (0.1 as a Single is 0.100000001490116).
// CStr and Print show a Single to its seven significant digits ("Str function",
// "Print # statement"): CSng(1 / 3) is 0.3333333. A declared Single past its range is
// Overflow (error 6); a Variant's Single "is promoted within the Variant" to a Double
// ("Variant data type").
#[test]
fn a_single_is_computed_and_shown_as_a_32_bit_float() {
    let out = printed(
        "",
        "    Dim s As Single, v, big As Single\n    s = 0.1\n\
         \x20   Debug.Print CSng(1 / 3); s * 3; CStr(CSng(2) / 3); \"|\"; CDbl(s); \"|\" & s * s\n\
         \x20   Debug.Print TypeName(s * s); \" \"; TypeName(s * 2); \" \"; TypeName(s * 2&); \" \"; TypeName(s / 2); \" \"; TypeName(s * 0.5)\n\
         \x20   s = 16777216: Debug.Print s + 1 = 16777216; CSng(16777217) = 16777216; CDbl(16777217) = 16777216\n\
         \x20   v = CSng(3E+38): v = v * 2: Debug.Print TypeName(v)\n\
         \x20   On Error Resume Next\n    big = 3E+38: big = big * 2\n    Debug.Print Err.Number; big",
    );
    assert_eq!(
        out,
        [
            " 0.3333333  0.3 0.6666667| 0.100000001490116 |0.01",
            "Single Single Double Single Double",
            "TrueTrueFalse",
            "Double",
            " 6  3E+38 ",
        ]
    );
}

// [MS-VBAL] 5.5.1.2.4, Let-coercion to String: a Single becomes the text CStr gives it, its
// seven significant digits ("Single data type"), a Date its date text, a LongLong its every
// digit. A library function's String parameter ("Replace function": expression, find and
// replace are Strings; "Left function", "InStr function", "Split function", "StrReverse
// function"), a String variable, a ByVal String parameter ([MS-VBAL] 5.3.1.11 let-coerces
// the argument to the parameter's type) and both operands of Like (5.6.9.5.7) take that text.
// `Replace(Rnd(), ".", "")` names a sheet in a real module: Excel's first Rnd is 0.7055475
// (KB 231847), the name "07055475", where a Double's 15 digits gave "0705547511577606".
#[test]
fn a_single_or_a_date_given_where_a_string_is_wanted_is_the_text_its_type_writes() {
    let out = printed(
        "Sub Show(ByVal t As String)\n    Debug.Print \"[\" & t & \"]\";\nEnd Sub\n",
        "    Dim s As Single, d As Date, k As LongLong, t As String\n    s = 1 / 3: d = #1/2/2024#: k = 9007199254740993^\n\
         \x20   Debug.Print Replace(Rnd(), \".\", \"\"); \"|\"; Replace(s, \".\", \",\"); \"|\"; Left(s, 20); \"|\"; Mid(s, 2); \"|\"; Right(CSng(2 / 3), 3)\n\
         \x20   Debug.Print InStrRev(s, \"3\"); StrComp(s, \"0.3333333\"); Split(s, \".\")(1); \"|\"; StrReverse(s); \"|\"; Trim(s); \"|\"; Val(s)\n\
         \x20   Debug.Print Left(d, 3); \"|\"; Replace(d, \"/\", \"-\"); \"|\"; Left(k, 20); \"|\"; s Like \"0.3333333\"; d Like \"1/2/*\"\n\
         \x20   t = s: Debug.Print t; \"|\";\n    t = Rnd(): Debug.Print t\n\
         \x20   Show s: Show d: Show CSng(0.1): Debug.Print",
    );
    assert_eq!(
        out,
        [
            "07055475|0,3333333|0.3333333|.3333333|667",
            " 9  0 3333333|3333333.0|0.3333333| 0.3333333 ",
            "1/2|1-2-2024|9007199254740993|TrueTrue",
            "0.3333333|0.533424",
            "[0.3333333][1/2/2024][0.1]",
        ]
    );
}

// "Currency data type": "64-bit (8-byte) numbers in an integer format, scaled by 10,000 to
// give a fixed-point number with 15 digits to the left of the decimal point and 4 digits to
// the right", -922,337,203,685,477.5808 to 922,337,203,685,477.5807; a value assigned to a
// Currency keeps four places, halves to even (as CCur, "Type conversion functions"). Sums of
// Currencies are exact (ten 0.1s are 1); [MS-VBAL] 5.6.9.3: a Currency with another Currency
// or an integral number is a Currency, its product rounded to four places; past the range
// Overflow (error 6).
#[test]
fn a_currency_is_a_scaled_64_bit_integer() {
    let out = printed(
        "",
        "    Dim c As Currency, d As Currency, i As Integer, e As Currency\n\
         \x20   For i = 1 To 10: c = c + 0.1: Next\n    Debug.Print c - 1; TypeName(c + 1); TypeName(c * i)\n\
         \x20   c = 1.5: d = 0.0001: Debug.Print c * d; CCur(2.5) * d + 0; CStr(c * d)\n\
         \x20   c = 0.12345678: Debug.Print c\n\
         \x20   On Error Resume Next\n    e = 922337203685477#: e = e * 10\n    Debug.Print Err.Number; e",
    );
    assert_eq!(out, [" 0 CurrencyCurrency", " 0.0002  0.0002 0.0002", " 0.1235 ", " 6  922337203685477 "]);
}

// [MS-VBAL] 5.6.9.3 and 5.6.9.3.1: an arithmetic operator let-coerces its operands to numbers,
// and a value that is none — an error value ("CVErr function": "a Variant of subtype Error")
// or a String that is no number — is run-time error 13, Type mismatch ("Type mismatch (Error
// 13)"), which On Error traps, the variable left as it was; 5.6.9.8.1: `Not` likewise. A
// String that is a number negates as the number.
#[test]
fn arithmetic_on_an_error_value_or_a_text_that_is_no_number_is_a_type_mismatch() {
    let out = printed(
        "",
        "    Dim x, e\n    e = CVErr(2042)\n    On Error Resume Next\n\
         \x20   x = CVErr(2007) + 1: Debug.Print Err.Number; IsEmpty(x): Err.Clear\n\
         \x20   x = e * 2: Debug.Print Err.Number: Err.Clear\n\
         \x20   x = -\"abc\": Debug.Print Err.Number: Err.Clear\n\
         \x20   x = Not \"abc\": Debug.Print Err.Number: Err.Clear\n\
         \x20   x = -e: Debug.Print Err.Number: Err.Clear\n\
         \x20   x = -\"12\": Debug.Print Err.Number; x; IsError(e)",
    );
    assert_eq!(out, [" 13 True", " 13 ", " 13 ", " 13 ", " 13 ", " 0 -12 True"]);
    let e = run("Sub Main()\n    Dim x\n    x = 1 + CVErr(2042)\nEnd Sub\n").unwrap_err();
    assert!(e.message.contains("Type mismatch (run-time error 13)"), "{e}");
    assert_eq!(e.span.unwrap().line, 3, "{e}");
}

// [MS-VBAL] 5.6.9.4 "& Operator": each operand is let-coerced to String, and 5.5.1.2
// ("Let-coercion from Error"): an Error let-coerced to any type but Variant is run-time error
// 13, Type mismatch. So `"x" & CVErr(2042)` raises 13 (trappable, the variable left as it
// was) where a formula's `&` would give #N/A and print "Error 2042" without the "x".
#[test]
fn joining_an_error_value_is_a_type_mismatch() {
    let out = printed(
        "",
        "    Dim x, e\n    e = CVErr(2042)\n    On Error Resume Next\n\
         \x20   x = \"x\" & CVErr(2042): Debug.Print Err.Number; IsEmpty(x): Err.Clear\n\
         \x20   x = e & \"y\": Debug.Print Err.Number; IsEmpty(x): Err.Clear\n\
         \x20   x = \"a\" & \"b\": Debug.Print Err.Number; x",
    );
    assert_eq!(out, [" 13 True", " 13 True", " 0 ab"]);
    let e = run("Sub Main()\n    Dim s\n    s = \"x\" & CVErr(2042)\nEnd Sub\n").unwrap_err();
    assert!(e.message.contains("Type mismatch (run-time error 13)"), "{e}");
    assert_eq!(e.span.unwrap().line, 3, "{e}");
}

// [MS-VBAL] 5.6.9.5 "Relational Operators": numeric operands compare as their values in the
// operation's type, a Double exactly: 0.1 + 0.2 is 0.30000000000000004, not 0.3, where a
// cell compares to 15 digits. A Boolean is the number it converts to ([MS-VBAL] 5.5.1.2.1,
// True is -1, False 0), so True = -1 and True < False. A Boolean against a String compares
// the String converted ("CBool": "True" and "False" are the Booleans, a number its value);
// a Date against a String the String's date ("CDate"). Select Case compares as `=` does.
#[test]
fn numbers_compare_exactly_and_booleans_as_their_numbers() {
    let out = printed(
        "",
        "    Dim b As Boolean, d As Date, x As Double\n    b = True: d = #1/2/2024#: x = 0.1 + 0.2\n\
         \x20   Debug.Print 0.1 + 0.2 = 0.3; 1 / 3 = 0.333333333333333; x > 0.3; x <> 0.3\n\
         \x20   Debug.Print True = -1; b = -1; b > 0; True < False; False = 0\n\
         \x20   Debug.Print b = \"True\"; b = \"-1\"; b = \"false\"; d = \"1/2/2024\"\n\
         \x20   Select Case x\n        Case 0.3: Debug.Print \"0.3\"\n        Case Else: Debug.Print \"else\"\n    End Select",
    );
    assert_eq!(out, ["FalseFalseTrueTrue", "TrueTrueFalseTrueTrue", "TrueTrueFalseTrue", "else"]);
}

// "Collection object", "Dictionary object": an item is a Variant, which keeps the type of the
// value added ("Variant data type": "numeric Variant data is maintained in its original data
// type"; [MS-VBAL] 3.3.2, the literal 5 is an Integer, 40000 a Long): TypeName of an item
// holding 5 is "Integer", VarType 2 ("VarType function"), and arithmetic on it an Integer's.
#[test]
fn a_collection_item_keeps_its_number_type() {
    let out = printed(
        "",
        "    Dim c As New Collection, d, n As Long\n    Set d = CreateObject(\"Scripting.Dictionary\")\n\
         \x20   n = 7\n    c.Add 5: c.Add 40000: c.Add 2.5: c.Add n, \"k\"\n    d.Add \"a\", 5\n\
         \x20   Debug.Print TypeName(c(1)); \" \"; VarType(c.Item(1)); TypeName(c(2)); \" \"; TypeName(c(3)); \" \"; TypeName(c(\"k\"))\n\
         \x20   Debug.Print TypeName(c(1) + 1); \" \"; TypeName(d(\"a\")); \" \"; TypeName(d.Item(\"a\"))",
    );
    assert_eq!(out, ["Integer  2 Long Double Long", "Integer Integer Integer"]);
}

// "& operator" (Office VBA reference): an expression that is not a string is converted to a
// String variant, and one Null operand is a zero-length string; a Boolean converted to a
// String is "True" or "False", as CStr gives ("Type conversion functions"), where a formula's
// `&` gives "TRUE".
#[test]
fn a_boolean_concatenated_is_true_or_false_as_vba_spells_it() {
    let out = printed(
        "",
        "    Dim b As Boolean, v As Variant\n    b = True\n    v = (1 > 2)\n\
         \x20   Debug.Print \"a\" & b & \"|\" & v & \"|\" & (3 = 3) & Null\n    Debug.Print b & v",
    );
    assert_eq!(out, ["aTrue|False|True", "TrueFalse"]);
}

// "+ operator" (Office VBA reference): a Currency with a Double is a Currency (the order of
// precision for addition ends Double, Currency, Decimal); "Currency data type": its range is
// ±922,337,203,685,477.5807, so a sum past it is Overflow (error 6), trappable, where the
// scaled operand 1E+300 overflowed the 128-bit arithmetic (a panic in a debug build).
#[test]
fn a_currency_sum_far_past_its_range_is_overflow() {
    let out = printed(
        "",
        "    Dim c As Currency, v\n    c = 1\n    On Error Resume Next\n    v = c + 1E+300\n\
         \x20   Debug.Print Err.Number\n    Err.Clear\n    v = c - 1E+300\n    Debug.Print Err.Number",
    );
    assert_eq!(out, [" 6 ", " 6 "]);
}

// [MS-VBAL] "* Operator" (5.6.9.3): a Currency times a Single, a Double or a String is a
// Double, declared and (in a Variant) held, so the product keeps every digit: `c * 0.03125`
// of the Currency 1 is 0.03125, where a Currency would round it to 0.0312 (halves to even);
// a Date times a number is a Double too. A Currency times an Integer stays a Currency (the
// standard table of 5.6.9.3). "/ operator" (Office VBA reference): the result "is usually a
// Double", and a Currency is none of the exceptions (Byte, Integer, Single; Decimal).
#[test]
fn a_currency_times_a_double_is_a_double() {
    let out = printed(
        "",
        "    Dim c As Currency, x As Double, v, d As Date\n    c = 1: x = 0.03125: v = c\n\
         \x20   Debug.Print c * x; TypeName(c * x); \" \"; TypeName(x * c); \" \"; TypeName(c * \"2\")\n\
         \x20   Debug.Print v * 0.03125; TypeName(v * 0.03125); \" \"; TypeName(c * 3); \" \"; TypeName(d * c)\n\
         \x20   Debug.Print c / 32; TypeName(c / 32)",
    );
    assert_eq!(out, [" 0.03125 Double Double Double", " 0.03125 Double Currency Double", " 0.03125 Double"]);
}

// "Array function": it returns "a Variant containing an array", each item a Variant holding
// its argument's value with its type ("Variant data type": "numeric Variant data is
// maintained in its original data type"); [MS-VBAL] 3.3.2: the literal 1 is an Integer,
// 40000 a Long, 2.5 a Double. So TypeName of `Array(1, 2)(0)` is "Integer" (VarType 2,
// "VarType function"), an item plus the Integer 1 is an Integer (5.6.9.3), and a copy of the
// array or ReDim Preserve keeps the items' types.
#[test]
fn an_array_function_item_keeps_its_literal_type() {
    let out = printed(
        "",
        "    Dim v, w, n As Long\n    n = 7\n    v = Array(1, 40000, 2.5, \"a\", n)\n\
         \x20   Debug.Print TypeName(v(0)); \" \"; VarType(v(0)); TypeName(v(1)); \" \"; TypeName(v(2)); \" \"; TypeName(v(3)); \" \"; TypeName(v(4))\n\
         \x20   w = v: ReDim Preserve w(5)\n\
         \x20   Debug.Print TypeName(v(0) + 1); \" \"; TypeName(w(0)); \" \"; TypeName(w(1))",
    );
    assert_eq!(out, ["Integer  2 Long Double String Long", "Integer Integer Long"]);
}

// "Comparison operators" (Office VBA reference): when both expressions are Variants and "one
// expression is numeric and the other is a string", "the numeric expression is less than the
// string expression"; its numeric data types are "Byte, Boolean, Integer, Long, Single,
// Double, Date, Currency, or Decimal". So a Variant holding True is less than a Variant
// holding "abc", either way round, where a formula puts TRUE after every text.
#[test]
fn a_variant_boolean_is_less_than_a_variant_string() {
    let out = printed(
        "",
        "    Dim v, s, n\n    v = True: s = \"abc\": n = 5\n\
         \x20   Debug.Print v < s; v > s; v = s; s > v; s <= v\n\
         \x20   Debug.Print n < s; s > n",
    );
    assert_eq!(out, ["TrueFalseFalseTrueFalse", "TrueTrue"]);
}

// "Date data type" (Office VBA language reference): a Date holds 1 January 100 (-657,434) to
// 31 December 9999, and "negative whole numbers represent dates before 30 December 1899";
// [MS-VBAL] 2.1.1.1: the fraction of a negative Date is its time counted forward (-1.25 is
// 29 December 1899, 6:00 AM). VBA's calendar is the proleptic Gregorian one on both sides of
// 1900 (no 1900-02-29: day 2 is 1 January 1900, a Monday), unlike the sheet's YEAR, which
// keeps Excel's 1900 system (its serial 1 is 1 January 1900). The serials and weekdays were
// worked out with Python's datetime (date(1800, 7, 4) - date(1899, 12, 30) = -36338 days, a
// Friday: Weekday 6 counted from Sunday, 5 from Monday).
#[test]
fn dates_before_1900_have_vba_years_months_days_and_weekdays() {
    let out = printed(
        "",
        "    Dim d As Date, t As Date\n    d = DateSerial(100, 1, 1)\n\
         \x20   Debug.Print CDbl(d); Year(d); Month(d); Day(d); Weekday(d); CStr(d)\n\
         \x20   d = DateSerial(1800, 7, 4)\n\
         \x20   Debug.Print CDbl(d); Year(d); Month(d); Day(d); Weekday(d); Weekday(d, 2); CStr(d); \" \"; Format(d, \"yyyy-mm-dd\")\n\
         \x20   d = DateSerial(1900, 1, 1)\n\
         \x20   Debug.Print CDbl(d); Year(d); Month(d); Day(d); Weekday(d); \" \"; Format(d, \"yyyy-mm-dd ddd\")\n\
         \x20   t = CDate(-1.25)\n\
         \x20   Debug.Print Year(t); Month(t); Day(t); Hour(t); \" \"; Format(t, \"yyyy-mm-dd hh:mm\"); \" \"; CStr(t)\n\
         \x20   Debug.Print Application.WorksheetFunction.Year(1); Year(Null) & \"|\"",
    );
    assert_eq!(
        out,
        [
            "-657434  100  1  1  6 1/1/100",
            "-36338  1800  7  4  6  5 7/4/1800 1800-07-04",
            " 2  1900  1  1  2  1900-01-01 Mon",
            " 1899  12  29  6  1899-12-29 06:00 12/29/1899 6:00:00 AM",
            " 1900 |",
        ]
    );
}

// "Date data type": a Date holds 1 January 100 to 31 December 9999; [MS-VBAL] 5.6.9.3.3, a
// Date plus a number is a Date, so `d + 1` of 12/31/9999 (or `d - 1` of 1/1/100) is past
// its range: "Overflow (Error 6)", trappable, as CDate(3E6) is ("Type conversion functions":
// a value outside the range of the type converted to is an error). Within the range the sum
// is the next day.
#[test]
fn a_date_sum_past_31_december_9999_is_overflow() {
    let out = printed(
        "",
        "    Dim d As Date, e As Date\n    On Error Resume Next\n    d = #12/30/9999#\n    e = d + 1\n\
         \x20   Debug.Print Err.Number; CStr(e)\n    Err.Clear\n    e = e + 1\n    Debug.Print Err.Number; CStr(e)\n\
         \x20   Err.Clear\n    d = DateSerial(100, 1, 1)\n    e = d - 1\n    Debug.Print Err.Number; CStr(e)\n\
         \x20   Err.Clear\n    e = CDate(3E6)\n    Debug.Print Err.Number",
    );
    assert_eq!(out, [" 0 12/31/9999", " 6 12/31/9999", " 6 12/31/9999", " 6 "]);
}

// [MS-VBAL] 5.6.9.3, "* Operator": a Date times a number is a Double, not
// a Date, and `^` is always a Double (5.6.9.3.8); only `+` and `-` of a Date and a number
// give a Date ("Date data type"). So `Now * 86400`, the seconds of a date, is no Overflow
// however far past 12/31/9999 (serial 2958465) the product goes.
#[test]
fn a_date_times_a_number_is_a_double_past_the_date_range() {
    let out = printed(
        "",
        "    Dim d As Date\n    d = #12/30/9999#\n    Debug.Print CDate(1) * 1E+7; TypeName(CDate(1) * 1E+7)\n\
         \x20   Debug.Print d * 24 * 3600; d ^ 2; TypeName(d * 24)",
    );
    assert_eq!(out, [" 10000000 Double", " 255611289600  8752509239296 Double"]);
}

// [MS-VBAL] 5.2.3.4 (Enum declarations): a variable declared with an enum type holds a Long,
// which starts at 0 ("Dim statement": "numeric variables are initialized to 0"). The
// libraries' enums (VBA's "VbCompareMethod", "VbVarType", Excel's "XlDirection", Office's
// "MsoTriState", each a page of Microsoft's object model reference) are such types, not
// objects: TypeName is "Long", never "Nothing".
#[test]
fn a_library_enum_type_declares_a_long() {
    let out = printed(
        "",
        "    Dim m As VbCompareMethod, v As VbVarType, d As XlDirection, t As MsoTriState\n\
         \x20   Debug.Print TypeName(m); TypeName(v); TypeName(d); TypeName(t); m + v + d + t\n\
         \x20   d = xlUp\n    Debug.Print TypeName(d); d",
    );
    assert_eq!(out, ["LongLongLongLong 0 ", "Long-4162 "]);
}
