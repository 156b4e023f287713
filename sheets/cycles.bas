Attribute VB_Name = "Cycles"
' Multi-pass turning cycles for old NC lathes (Bondar; docs/domain.md §2), as macros that emit
' the blocks. Written as the paper writes them: R-parameters, numbered labels, and
' "If … Then GoTo Nn". X is a diameter, Z runs along the spindle with the face at Z0.
'
'   ncsheet run part.xlsx cycles.bas --sub L16 --arg X=30 --arg W=40 --dialect nc31
'   ncsheet run part.xlsx cycles.bas --sub L17 --dialect linuxcnc -o l17.ngc
'   ncsheet run part.xlsx cycles.bas --sub L13 --arg R0=3 --arg R4=2.5
'   ncsheet run part.xlsx cycles.bas --dialect nc31 --subprograms    ' the cycles called, not unrolled
'
' L16  zigzag roughing of an open surface: cuts along Z toward the chuck and back, stepping
'      X down by P between the cuts, until the final diameter X plus the allowance A. It
'      also carries its NC31 subprogram (L16Subprogram): with `run --subprograms` the NC31
'      program calls it, `L16 X30 W40 A0.5 P2 B44 F0.2`, instead of holding every pass.
' L17  loop: the finish contour L03, shifted out in X by a shrinking amount, cut once per pass
'      from the face toward the chuck, each pass returning by rapid. Its NC31 subprogram
'      calls L03 per pass, `L17 A0.5 P3 B44 F0.15`; L03's fillet is cut as the lines the
'      program's arcs become on the NC31 (Nc.ChordsCW, within --arc-tol).
' L13  plunge ("descent") into a recess whose bottom is a contour of lines and an arc, a
'      grooving tool of width R0 stepping along Z by R4, with a dwell of R5 seconds. Its NC31
'      subprogram works the bottom out itself (L14): the lines by the paper's formula (1),
'      the arc's square root, which the control's arithmetic lacks, by Newton's iteration.
Option Explicit

' How far (mm, in X as a radius) the tool stays off the blank wherever it moves in rapid.
Const Clear As Double = 1

' ---- L16 -------------------------------------------------------------------------------

' X: final diameter; W: loop length along Z; A: finishing allowance on X; P: depth of cut
' (in X, as the control's X words); Stock: the blank's diameter; F: feed (mm/rev).
Sub L16(Optional X As Double = 30, Optional W As Double = 40, Optional A As Double = 0.5, _
        Optional P As Double = 2, Optional Stock As Double = 44, Optional F As Double = 0.2)
    Dim XT As Double, XK As Double, R1 As Double
    Begin "L16", 700, F, 1
    Nc.Comment "L16 zigzag X" & X & " W" & W & " A" & A & " P" & P
    L16Subprogram
    Nc.Cycle "L16", X, W, A, P, Stock, F   ' the blocks to Nc.EndCycle are this call of it
    XK = X + A                      ' the lowest diameter a pass may cut
    XT = Stock
    R1 = 0                          ' where the loop is: 0 at the face, W toward the chuck
    Nc.Rapid Stock + 2 * Clear, 1
    Nc.Rapid Stock + 2 * Clear, 0
N10:
    XT = XT - P
    If XT < XK Then XT = XK         ' the last pass takes what is left, no more
    Nc.Line XT, , F                 ' in to the pass diameter
    If R1 = 0 Then R1 = W Else R1 = 0
    Nc.Line , -R1                   ' along Z: toward the chuck, next time back
    If XT > XK Then GoTo N10
    Nc.Rapid Stock + 2 * Clear, -R1
    Nc.Rapid Stock + 2 * Clear, 1
    Nc.EndCycle
    Finish
End Sub

' L16 above as the NC31 runs it (docs/domain.md §2, "Calls with values"): the call's X W A P,
' the blank's diameter B and the feed F land in R1-R6. R7 is the lowest pass diameter X + A,
' R8 the pass diameter, R9 where the cut along Z ends (0 at the face, W toward the chuck),
' R10 the diameter the rapids keep, Clear above the blank. ncsheet checks, before it writes
' the call, that this runs exactly the blocks the Sub emitted.
Sub L16Subprogram()
    Nc.Subprogram "L16 XR1 WR2 AR3 PR4 BR5 FR6", _
        "N1 R7=R1+R3", "N2 R8=R5", "N3 R9=0", "N4 R10=R5+" & 2 * Clear, _
        "N5 XR10 Z1 E", "N6 XR10 Z0 E", _
        "N7 R8=R8-R4", "N8 IF R8<R7 THEN R8=R7", "N9 XR8 FR6", _
        "N10 IF R9=0 THEN R9=R2 GOTO N12", "N11 R9=0", "N12 Z-R9", _
        "N13 IF R8>R7 THEN GOTO N7", _
        "N14 XR10 Z-R9 E", "N15 XR10 Z1 E", "N16 M17"
End Sub

' ---- L17 and its contour L03 --------------------------------------------------------------

' A: allowance left on the contour; P: depth of cut per pass (in X); Stock: the blank's
' diameter; F: feed.
Sub L17(Optional A As Double = 0.5, Optional P As Double = 3, Optional Stock As Double = 44, _
        Optional F As Double = 0.15)
    Dim R2 As Double
    Begin "L17", 700, F, 1
    Nc.Comment "L17 loop A" & A & " P" & P
    L17Subprogram
    Nc.Cycle "L17", A, P, Stock, F  ' the blocks to Nc.EndCycle are this call of it
    R2 = Stock - 20                 ' the thickest layer: the contour's smallest diameter is 20
N10:
    R2 = R2 - P
    If R2 < A Then R2 = A
    L03 R2, Stock, F                ' one pass along the contour, R2 above it
    If R2 > A Then GoTo N10
    Nc.EndCycle
    Finish
End Sub

' L17 above as the NC31 runs it: the call's A P, the blank's diameter B and the feed F land
' in R2-R5 (R2 the allowance and R3 the depth of cut, as the paper numbers them); R6 is the
' pass's shift, which L03 reads.
Sub L17Subprogram()
    Nc.Subprogram "L17 AR2 PR3 BR4 FR5", _
        "N1 R6=R4-20", "N2 R6=R6-R3", "N3 IF R6<R2 THEN R6=R2", "N4 L03", _
        "N5 IF R6>R2 THEN GOTO N2", "N6 M17"
    ' L03 cuts its fillet as lines (Nc.ChordsCW, within --arc-tol): only a control without arcs
    ' runs the subprograms; elsewhere the cycle is written unrolled, with its arcs, and
    ' --arc-tol does not apply.
    If Nc.Dialect = "nc31" Or Nc.Dialect = "nc81" Then L03Subprogram
End Sub

' The finish contour, shifted out in X by dx: a face-side diameter 20, a fillet of radius 5
' up to diameter 30, a cylinder, and a taper to diameter 40. Cut from the face toward the
' chuck, then back by rapid.
Sub L03(dx As Double, Stock As Double, F As Double)
    Nc.Rapid 20 + dx, 2
    Nc.Line 20 + dx, 0, F
    Nc.Line 20 + dx, -10
    Nc.ArcCW 30 + dx, -15, 30 + dx, -10    ' centre at diameter 30, Z-10: a concave fillet
    Nc.Line 30 + dx, -25
    Nc.Line 40 + dx, -35
    Nc.Rapid Stock + 2 * Clear, -35
    Nc.Rapid Stock + 2 * Clear, 2
End Sub

' L03 above as the NC31 runs it, shifted by R6, from the blank R4 at the feed R5. The control
' has no arcs: the fillet is the lines Nc.ChordsCW gives for it (at shift 0), each end moved
' out by R6 in R7, as the program's own ArcCW becomes.
Sub L03Subprogram()
    Dim c, k As Long, n As Long, body As String
    body = "N1 R7=20+R6" & vbLf & "N2 XR7 Z2 E" & vbLf & "N3 XR7 Z0 FR5" & vbLf & "N4 XR7 Z-10"
    c = Nc.ChordsCW(20, -10, 30, -15, 30, -10)
    n = 5
    For k = LBound(c) To UBound(c) Step 2
        body = body & vbLf & "N" & n & " R7=R6+" & c(k) & vbLf & "N" & (n + 1) & " XR7 Z" & c(k + 1)
        n = n + 2
    Next
    body = body & vbLf & "N" & n & " R7=30+R6" & vbLf & "N" & (n + 1) & " XR7 Z-25" & vbLf & _
        "N" & (n + 2) & " R7=40+R6" & vbLf & "N" & (n + 3) & " XR7 Z-35" & vbLf & _
        "N" & (n + 4) & " R7=R4+" & 2 * Clear & vbLf & "N" & (n + 5) & " XR7 Z-35 E" & vbLf & _
        "N" & (n + 6) & " XR7 Z2 E M17"
    Nc.Subprogram "L03", body
End Sub

' ---- L13 -------------------------------------------------------------------------------

' XStart: the diameter of the part where the recess is (the tool plunges from Clear above it
' and returns there); ZRight, ZLeft: the recess's
' ends; R0: tool width (the programmed point is its right corner); R4: step along Z;
' R5: dwell (s); A: allowance on the bottom; F: plunge feed; Shift: how far along Z the
' recess of Bottom lies from its place at Z-10…-30; T: the grooving tool, R0 wide.
Sub L13(Optional XStart As Double = 44, Optional ZRight As Double = -10, Optional ZLeft As Double = -30, _
        Optional R0 As Double = 3, Optional R4 As Double = 2.5, Optional R5 As Double = 0.5, _
        Optional A As Double = 0, Optional F As Double = 0.05, Optional Shift As Double = 0, _
        Optional T As Double = 2)
    Dim Z As Double, R3 As Double, X As Double, XSafe As Double
    Begin "L13", 500, F, T
    XSafe = XStart + 2 * Clear
    Nc.Comment "L13 plunge R0=" & R0 & " R4=" & R4
    L13Subprogram
    Nc.Cycle "L13", XStart, ZRight, ZLeft, R0, R4, R5, A, F, Shift
    Z = ZRight                      ' the tool's right corner
    R3 = (ZRight - ZLeft) - R0      ' width still to plunge after this one
    Nc.Rapid XSafe, 1
    Nc.Rapid XSafe, Z
N10:
    X = Deepest(Z - R0 - Shift, Z - Shift) + A   ' the larger of the bottom under the two corners
    Nc.Line X, Z, F
    Nc.Dwell R5
    Nc.Rapid XSafe, Z
    If R3 <= 0 Then GoTo N20
    If R3 < R4 Then Z = Z - R3 Else Z = Z - R4
    R3 = R3 - R4
    Nc.Rapid XSafe, Z
    GoTo N10
N20:
    Nc.Rapid XSafe, 1
    Nc.EndCycle
    Finish
End Sub

' L13 above as the NC31 runs it. The call's letters: X the part's diameter (R6), Z and K the
' recess's right and left ends (R7, R8; R7 then follows the tool's right corner), P the tool's
' width (R0, as the paper's `PR0`), W the step along Z (R4), D the dwell (R5), A the
' allowance (R9), F the feed (R10), Q Bottom's shift along Z (R11). R3 is the width still to
' plunge and R1 the plunge's diameter, as the paper names them; R12 the safe diameter.
' Deepest's three bottoms are L14's, with R20 in and R21 out.
Sub L13Subprogram()
    Nc.Subprogram "L13 XR6 ZR7 KR8 PR0 WR4 DR5 AR9 FR10 QR11", _
        "N1 R12=R6+" & 2 * Clear, "N2 R3=R7-R8-R0", "N3 XR12 Z1 E", "N4 XR12 ZR7 E", _
        "N5 R20=R7-R0-R11", "N6 L14", "N7 R1=R21", "N8 R20=R7-R11", "N9 L14", "N10 IF R21>R1 THEN R1=R21", _
        "N11 IF R7-R0-R11>-22 THEN GOTO N16", "N12 IF R7-R11<-22 THEN GOTO N16", _
        "N13 R20=-22", "N14 L14", "N15 IF R21>R1 THEN R1=R21", _
        "N16 R1=R1+R9", "N17 XR1 ZR7 FR10", "N18 G4 DR5", "N19 XR12 ZR7 E", _
        "N20 IF R3<=0 THEN GOTO N25", "N21 IF R3<R4 THEN R7=R7-R3 GOTO N23", "N22 R7=R7-R4", _
        "N23 R3=R3-R4", "N24 XR12 ZR7 E GOTO N5", "N25 XR12 Z1 E M17"
    ' Bottom(R20) into R21, piece by piece as Bottom; the arc's root by Newton's iteration from
    ' the radius down (R23), which stops where it no longer falls: the root to the last digit.
    Nc.Subprogram "L14", _
        "N1 IF R20>=-14 THEN R21=36+(R20+10)*(30-36)/(-14+10) GOTO N11", _
        "N2 IF R20>=-18 THEN R21=30 GOTO N11", "N3 IF R20>=-26 THEN GOTO N6", _
        "N4 IF R20>=-30 THEN R21=30+(R20+26)*(36-30)/(-30+26) GOTO N11", "N5 R21=36 GOTO N11", _
        "N6 R22=5*5-(R20+22)*(R20+22)", "N7 R23=5", "N8 R24=(R23+R22/R23)/2", _
        "N9 IF R24<R23 THEN R23=R24 GOTO N8", "N10 R21=2*(12+R23)", "N11 M17"
End Sub

' The recess bottom's diameter at Z: a taper down, a flat, an arc bulging up by 2 (radius 5,
' centre at diameter 24, Z-22), a flat, a taper up.
' L14 (in L13Subprogram) is this function as the NC31 runs it: change both together.
Function Bottom(Z As Double) As Double
    Select Case Z
        Case Is >= -14
            Bottom = 36 + (Z + 10) * (30 - 36) / (-14 + 10)   ' R = (Z-Z1)(X2-X1)/(Z2-Z1) + X1
        Case Is >= -18
            Bottom = 30
        Case Is >= -26
            Bottom = 2 * (12 + Sqr(5 ^ 2 - (Z + 22) ^ 2))    ' the circle solved for X (radius)
        Case Is >= -30
            Bottom = 30 + (Z + 26) * (36 - 30) / (-30 + 26)
        Case Else
            Bottom = 36
    End Select
End Function

' The highest bottom under a tool between ZL and ZR: the paper takes the larger of the two
' corners, which is enough for lines and hollows; a bulging arc's top between them counts too.
Function Deepest(ZL As Double, ZR As Double) As Double
    Deepest = Bottom(ZL)
    If Bottom(ZR) > Deepest Then Deepest = Bottom(ZR)
    If ZL <= -22 And ZR >= -22 Then
        If Bottom(-22) > Deepest Then Deepest = Bottom(-22)
    End If
End Function

' ---- shared ------------------------------------------------------------------------------

' The cycle's start: its name, its tool (1 the turning tool, 2 the 3 mm grooving tool), feed
' per revolution, the spindle at `speed` 1/min.
Sub Begin(name As String, speed As Double, F As Double, tool As Double)
    Nc.Name = name
    Nc.Machine = "lathe"
    Nc.Tool tool
    Nc.FeedPerRev F
    Nc.Spindle speed
End Sub

Sub Finish()
    Nc.Spindle 0
End Sub

' One part from a 44 mm blank, each cycle with its own tool: L16 roughs the blank to the
' contour's largest diameter (40, plus the allowance) over the contour's length (35), L17
' finishes the contour L03 under it in passes, and L13 plunges the recess with the grooving
' tool behind the contour, from Z-40 to Z-60 (Bottom's recess shifted 30 along Z).
Sub Main()
    L16 40, 35
    L17
    L13 44, -40, -60, 3, 2.5, 0.5, 0, 0.05, -30
    Nc.Name = "CYCLES"
End Sub
