Attribute VB_Name = "Chamfer"
' Chamfer coordinates on an NC lathe — the macro Tamul & Olt proposed (docs/domain.md §1): the
' sheet holds only the inputs and the results, and this macro does the arithmetic.
'
' It reads D, f, alpha, r, eA, eB (shaft diameter, chamfer length along Z, chamfer angle to
' the Z axis in degrees, insert nose radius, clearances past the chamfer ends A and B), computes
' the theoretical tool tip at the start T1 (XA, ZA) and at the end T2 (XB, ZB) of an outer
' chamfer with the paper's formulas 1–14, checks them against ncsheet's CHAMFER_XA … sheet
' functions, writes XA, ZA, XB, ZB to the sheet and emits the cut: rapid to T1, feed along the
' chamfer to T2, retract.
'
' Cells: the workbook's defined names D, f, alpha, r, eA, eB, XA, ZA, XB, ZB when it has them,
' else rows labelled as sheets/chamfer.csv labels them ("input", name, first case's value),
' else the fixed layout below (column B of the active sheet: inputs B2:B7, results B9:B12).
' X is a diameter.
'
'   ncsheet run chamfer.xlsx chamfer.bas --sheet Outer --dialect linuxcnc -o chamfer.ngc
'   ncsheet run chamfer.xlsx chamfer.bas --sheet Pipe --arg kind=pipe --arg feed=0.08 --save out.xlsx
Option Explicit

Const Pi As Double = 3.14159265358979

' kind: "outer" (formulas 1-14 here), or "pipe" / "blind" (inner chamfers, by CHAMFER_XA …).
' feed: mm per revolution along the chamfer; speed: spindle rev/min; tool: the tool number;
' clear: how far (mm) the tool's nose stays off the part wherever it moves in rapid.
Sub Main(Optional kind As String = "outer", Optional feed As Double = 0.1, Optional speed As Double = 800, _
         Optional tool As Double = 1, Optional clear As Double = 1)
    Dim D As Double, f As Double, alpha As Double, r As Double, eA As Double, eB As Double
    Dim XA As Double, ZA As Double, XB As Double, ZB As Double

    D = Range(Place("D", "B2")).Value
    f = Range(Place("f", "B3")).Value
    alpha = Range(Place("alpha", "B4")).Value
    ' Excel reserves the name r (a row in R1C1 style), so a workbook may call it r_.
    r = Range(Place("r_", Place("r", "B5"))).Value
    eA = Range(Place("eA", "B6")).Value
    eB = Range(Place("eB", "B7")).Value
    If alpha <= 0 Or alpha >= 90 Or r < 0 Or D <= 0 Or f <= 0 Then
        MsgBox "no chamfer has D=" & D & " f=" & f & " alpha=" & alpha & " r=" & r
        End
    End If

    If kind = "outer" Then
        OuterChamfer D, f, alpha, r, eA, eB, XA, ZA, XB, ZB
    Else
        XA = CHAMFER_XA(kind, D, f, alpha, r, eA, eB)
        ZA = CHAMFER_ZA(kind, D, f, alpha, r, eA, eB)
        XB = CHAMFER_XB(kind, D, f, alpha, r, eA, eB)
        ZB = CHAMFER_ZB(kind, D, f, alpha, r, eA, eB)
    End If
    Check "XA", XA, CHAMFER_XA(kind, D, f, alpha, r, eA, eB)
    Check "ZA", ZA, CHAMFER_ZA(kind, D, f, alpha, r, eA, eB)
    Check "XB", XB, CHAMFER_XB(kind, D, f, alpha, r, eA, eB)
    Check "ZB", ZB, CHAMFER_ZB(kind, D, f, alpha, r, eA, eB)

    ' The results go where the workbook names them; into the fixed layout's B9:B12 only when
    ' the inputs came from it too. A workbook that names its inputs but not its results (the
    ' paper's Excel model, sheets/chamfer.xlsx, computes XA … ZB with formulas in G6:G9) is
    ' left as it is: B9:B12 there hold inputs.
    Dim fixedLayout As Boolean
    fixedLayout = (Place("D", "B2") = "B2")
    PutResult "XA", "B9", XA, fixedLayout
    PutResult "ZA", "B10", ZA, fixedLayout
    PutResult "XB", "B11", XB, fixedLayout
    PutResult "ZB", "B12", ZB, fixedLayout
    Debug.Print "XA=" & Format(XA, "0.000") & " ZA=" & Format(ZA, "0.000") & _
                " XB=" & Format(XB, "0.000") & " ZB=" & Format(ZB, "0.000")

    Cut kind, alpha, XA, ZA, XB, ZB, feed, speed, tool, clear
End Sub

' The paper's formulas 1-14 for the outer chamfer (exact for every angle).
Sub OuterChamfer(ByVal D, ByVal f, ByVal alpha, ByVal r, ByVal eA, ByVal eB, XA, ZA, XB, ZB)
    Dim beta As Double, AC1 As Double, AD As Double, CD As Double, A1D As Double
    Dim BE As Double, EF As Double, B1F As Double, B1E As Double, f1 As Double
    Dim t As Double

    t = Tan(alpha * Pi / 180)
    beta = Pi / 2 - alpha * Pi / 180          ' 1
    AC1 = r / Sin(beta)                        ' 2  A'C
    AD = eA + r                                ' 3
    CD = AD * t                                ' 4
    A1D = CD + AC1                             ' 5  A'D
    XA = D + (A1D - r) * 2                     ' 6
    ZA = -(f + AD + r)                         ' 7
    BE = eB + r                                ' 8
    EF = BE * t                                ' 9
    B1F = r / Sin(beta)                        ' 10 B'F
    B1E = EF - B1F                             ' 11 B'E
    f1 = f * t                                 ' 12 f'
    XB = D - (f1 + B1E + r) * 2                ' 13
    ZB = eB                                    ' 14
End Sub

' Warns (on standard error) when our arithmetic and the sheet function disagree.
Sub Check(what As String, ours As Double, sheet As Double)
    If Abs(ours - sheet) > 0.000001 Then
        MsgBox what & ": the macro gives " & ours & ", CHAMFER_" & what & " gives " & sheet
    End If
End Sub

' The cut from T1 to T2. The nose at T1 touches the chamfer's line (and, in a blind bore, the
' bottom), so the tool comes in rapid only to P, T1 moved off the part far enough that the nose
' is `clear` away from the chamfer's line and from the cylinder, bore wall or bottom next to it:
'   outer  P = T1 out by clear / cos(alpha) (in X, a radius)
'   pipe   P = T1 in toward the axis by clear / cos(alpha)
'   blind  P = T1 in toward the axis by clear and up off the bottom by clear
' (moving the nose by d changes its distance to a line with unit normal n by d·n, and these
' moves make d·n at least `clear` for each line). From P it feeds to T1, cuts to T2 off the
' face, and retracts in rapid along +Z, away from the face, then back to the start.
Sub Cut(kind As String, alpha As Double, XA As Double, ZA As Double, XB As Double, ZB As Double, _
        feed As Double, speed As Double, tool As Double, clear As Double)
    Dim safeZ As Double, PX As Double, PZ As Double, c As Double
    c = Cos(alpha * Pi / 180)
    Select Case kind
        Case "outer"
            PX = XA + 2 * clear / c
            PZ = ZA
        Case "pipe"
            PX = XA - 2 * clear / c
            PZ = ZA
        Case Else
            PX = XA - 2 * clear
            PZ = ZA + clear
    End Select
    If PX <= 0 Then
        MsgBox "the bore is too small to approach T1 with " & clear & " mm clearance"
        End
    End If
    safeZ = ZB + clear + 1
    Nc.Name = "CHAMFER"
    Nc.Machine = "lathe"
    Nc.Comment kind & " chamfer, tool tip T1 to T2"
    Nc.Tool tool
    Nc.FeedPerRev feed
    Nc.Spindle speed
    Nc.Rapid PX, safeZ
    Nc.Rapid PX, PZ
    Nc.Line XA, ZA
    Nc.Line XB, ZB
    Nc.Rapid XB, safeZ
    Nc.Rapid PX, safeZ
    Nc.Spindle 0
End Sub

' Writes a result into the cell the workbook names, else (in the fixed layout) the fixed address.
Sub PutResult(name As String, fixed As String, v As Double, fixedLayout As Boolean)
    If IsObject(Evaluate(name)) Then
        Range(name).Value = v
    ElseIf fixedLayout Then
        Range(fixed).Value = v
    End If
End Sub

' A defined name of the workbook if it names cells; else, on a sheet laid out as
' sheets/chamfer.csv (rows "input", name, value, …), the value beside the name's label (its
' first case); else the fixed address.
Function Place(name As String, fixed As String) As String
    If IsObject(Evaluate(name)) Then
        Place = name
    ElseIf LabelRow(name) > 0 Then
        Place = "C" & LabelRow(name)
    Else
        Place = fixed
    End If
End Function

' The row of an input labelled `name` in column B (column A saying "input"), or 0.
' A cell holding an error (a formula of another sheet's making) is no label.
Function LabelRow(name As String) As Long
    Dim r As Long, kind As Variant, label As Variant
    LabelRow = 0
    For r = 1 To 50
        kind = Range("A" & r).Value
        label = Range("B" & r).Value
        If Not IsError(kind) And Not IsError(label) Then
            If kind = "input" And label = name Then
                LabelRow = r
                Exit Function
            End If
        End If
    Next r
End Function
