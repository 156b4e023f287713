//! Macro source to [`Module`]: runs the one pest parser (`Rule::module`, crates/ncsheet/grammar/macro.pest)
//! and builds statements here and expressions through the formula builder's Pratt table
//! ([`build_expr`]), which hands back the primaries only macros have (variables, member
//! paths, `[B3]`) through [`HostPrimaries`].
//!
//! Names are resolved while building, once, by `resolve.rs`.

use crate::formula::limits;
use std::cell::{Cell, RefCell};
use std::ops::Range;
use std::rc::Rc;

use pest::iterators::Pair;
use pest::Parser;

use crate::eval::functions::Registry;
use crate::formula::address::Pos;
use crate::formula::ast::{BinOp, Expr, ExprKind, SheetId, Span as ByteSpan};
use crate::formula::parse::{
    build_expr, expected_kinds, from_pest_with, is_operator, FormulaGrammar, HostPrimaries, ParseContext, ParseError,
    Rule,
};

use super::ast::*;
use super::collections::new_class;
use super::const_order::ModuleConst;
use super::resolve::{lower_bare, refusal, FORBIDDEN};

/// Where byte offsets of the source fall in lines and columns.
pub struct Lines {
    starts: Vec<usize>,
    /// The last place asked for (offset, its span): the next place on the same line is
    /// counted on from there, so 100,000 statements on one line cost time in proportion.
    last: Cell<(usize, Span)>,
}

impl Lines {
    pub fn new(src: &str) -> Lines {
        let mut starts = vec![0];
        starts.extend(src.match_indices('\n').map(|(i, _)| i + 1));
        Lines { starts, last: Cell::new((0, Span { line: 1, col: 1 })) }
    }

    pub fn span(&self, src: &str, offset: usize) -> Span {
        let offset = offset.min(src.len());
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let (last_offset, last) = self.last.get();
        let on_last_line = last.line as usize == line + 1 && src.is_char_boundary(last_offset);
        // A place just before the last one (an expression's start after its end was asked
        // for) is counted back from it, nearer than the line's start, so that asking out of
        // order stays linear too.
        let nearer_last = offset < last_offset && last_offset - offset < offset - self.starts[line];
        let back = match src.get(offset..last_offset) {
            Some(between) if on_last_line && nearer_last => Some(between.chars().count()),
            _ => None,
        };
        let col = match back {
            Some(stepped) => {
                super::count(&super::COLUMNS_STEPPED, stepped as u64);
                last.col - 1 - stepped as u32
            }
            None => {
                let from_last = on_last_line && last_offset <= offset;
                let (from, col_from) = if from_last { (last_offset, last.col - 1) } else { (self.starts[line], 0) };
                let stepped = src.get(from..offset).map_or(0, |s| s.chars().count());
                super::count(&super::COLUMNS_STEPPED, stepped as u64);
                stepped as u32 + col_from
            }
        };
        let span = Span { line: line as u32 + 1, col: col + 1 };
        self.last.set((offset, span));
        span
    }

    /// The text of a 1-based line, without its line break.
    pub fn text<'s>(&self, src: &'s str, line: u32) -> &'s str {
        let Some(&start) = self.starts.get(line as usize - 1) else { return "" };
        let end = self.starts.get(line as usize).map_or(src.len(), |&e| e);
        src[start..end].trim_end_matches(['\n', '\r'])
    }
}

/// A syntax error: where (byte offset) and why.
pub type SyntaxError = ParseError;

pub(super) type Res<T> = Result<T, ParseError>;

/// Parses a module. `sheets` resolves sheet names written in `[Sheet2!A1]` brackets.
/// `objects`: names (lower case) that are objects besides the language's own: the sheets'
/// code names, `me` in a document module.
pub fn parse_module(
    src: &str,
    sheets: &dyn Fn(&str) -> Option<SheetId>,
    objects: &[String],
    parts: &[Part],
) -> Result<Module, SyntaxError> {
    parse_module_with_files(src, sheets, objects, parts, false)
}

/// [`parse_module`] for a run that has files (`files.rs`): `Open`, `Print #`, `FreeFile`,
/// `CreateObject("Scripting.FileSystemObject")` … are built instead of refused by name.
pub fn parse_module_with_files(
    src: &str,
    sheets: &dyn Fn(&str) -> Option<SheetId>,
    objects: &[String],
    parts: &[Part],
    files: bool,
) -> Result<Module, SyntaxError> {
    let prepared = super::conditional::prepare(src)?;
    let reader = Reader { sheets, objects, parts, files };
    match module_pairs(&prepared) {
        Ok(pairs) => build_module(&prepared, pairs, Vec::new(), reader),
        Err(first) => {
            let (blanked, confined) = confine_to_procedures(&prepared, first)?;
            let pairs = module_pairs(&blanked)?;
            build_module(&blanked, pairs, confined, reader)
        }
    }
}

/// What [`parse_module_with_files`] reads a module with, beside its text.
#[derive(Clone, Copy)]
struct Reader<'r> {
    sheets: &'r dyn Fn(&str) -> Option<SheetId>,
    objects: &'r [String],
    parts: &'r [Part],
    files: bool,
}

/// The module `src` as the grammar read it (`pairs`); `confined`: the procedures the grammar
/// refused, by the byte range of their first line, each with its error ([`confine_to_procedures`]).
fn build_module(
    src: &str,
    mut pairs: pest::iterators::Pairs<'_, Rule>,
    mut confined: Vec<Confined>,
    reader: Reader,
) -> Result<Module, SyntaxError> {
    let Reader { sheets, objects, parts, files } = reader;
    let module = pairs.next().expect("module rule");
    let items: Vec<Pair<Rule>> = module.into_inner().collect();
    let mut b = Build::new(src, sheets, &items, parts)?;
    b.objects = objects;
    b.files = files;
    b.sheet_function_vars = super::resolve::sheet_function_aliases(src);
    b.declared =
        items.iter().filter(|i| i.as_rule() == Rule::declare_stmt).filter_map(|i| declared_name(i.as_str())).collect();
    let type_names = items.iter().filter(|i| i.as_rule() == Rule::type_def);
    let mut types = b.types.borrow_mut();
    for (i, item) in type_names.enumerate() {
        let name = name_of(&find(&kids(item), Rule::ident).expect("type name"));
        types.entry(name.to_ascii_lowercase()).or_insert(i);
    }
    drop(types);
    let mut out = Module { base: 0, classes: super::classes::class_defs(parts), ..Module::default() };
    b.declare_project_globals(&items);
    out.globals = b.module_constants(&items)?;
    for item in items {
        match item.as_rule() {
            Rule::type_def => {
                let t = b.type_def(item)?;
                out.types.push(t);
            }
            Rule::option_stmt => b.option(item)?,
            Rule::deftype_stmt => {
                b.current_part.set(b.part_at(start(&item)));
                b.deftype(&item)?;
            }
            // Built with the constants, in the order of what they read (`module_constants`).
            Rule::enum_def => {}
            Rule::const_stmt if b.standard(b.part_at(start(&item))) => {}
            Rule::implements_stmt => {
                let part = b.part_at(start(&item));
                let interface = name_of(&find(&kids(&item), Rule::ident).expect("interface name"));
                match out.classes.iter_mut().find(|c| c.part == part) {
                    Some(class) => class.implements.push(interface),
                    None => return Err(b.error_at(&item, "Implements belongs in a class module")),
                }
            }
            // A DLL's procedure: declared, never callable (`resolve.rs` refuses a call of it).
            Rule::declare_stmt => {}
            // A procedure that does not compile fails when it runs, not its module: VBA
            // compiles a procedure when it is first called.
            Rule::sub_def | Rule::function_def | Rule::property_def => {
                b.current_part.set(b.part_at(start(&item)));
                let refused = confined.iter().position(|(head, _)| head.contains(&start(&item)));
                let p = match refused.map(|k| confined.swap_remove(k).1) {
                    Some(e) => b.failed_proc(&item, e),
                    None => b.proc(item.clone()).unwrap_or_else(|e| b.failed_proc(&item, e)),
                };
                out.procs.push(p);
            }
            Rule::dim_stmt | Rule::const_stmt => {
                let at = start(&item);
                let part = b.part_at(at);
                b.current_part.set(part);
                let public = item.as_str().trim_start().get(..6).is_some_and(|w| w.eq_ignore_ascii_case("public"));
                b.building_globals.set(true);
                let s = b.statement(item)?.expect("a declaration");
                b.building_globals.set(false);
                match out.classes.iter_mut().find(|c| c.part == part) {
                    // A class module's own variables: each of its objects has them.
                    Some(class) => {
                        if public {
                            refuse_public_in_object_module(&s, at)?;
                            class.public.extend(declared_names(&s));
                        }
                        class.fields.push(s);
                    }
                    None => out.globals.push(s),
                }
            }
            _ => {}
        }
    }
    out.globals.extend(super::classes::default_instance_declarations(&b.parts));
    out.parts = b.parts.clone();
    out.public_names = b.public_names();
    out.options = b.options.take();
    let first = out.options.first().copied().unwrap_or_default();
    out.explicit = first.explicit;
    out.base = first.base;
    out.text_compare = first.text_compare;
    out.nodes = b.nodes.into_inner();
    Ok(out)
}

/// The items of module `src` (its conditional compilation already applied) as the grammar
/// reads them, after the checks that keep its nesting within the parser's stack.
fn module_pairs(src: &str) -> Res<pest::iterators::Pairs<'_, Rule>> {
    // Every reading of source by the grammar, whole modules and procedures read alone.
    super::count(&super::SOURCE_PARSED, src.len() as u64);
    limits::check_nesting(src, limits::Language::Macro)?;
    limits::check_block_nesting(src)?;
    FormulaGrammar::parse(Rule::module, src).map_err(from_pest)
}

/// The first error of the grammar in module `src` read on its own, its names not resolved,
/// that no procedure confines ([`confine_to_procedures`]).
pub(super) fn grammar_error(src: &str) -> Option<SyntaxError> {
    let prepared = match super::conditional::prepare(src) {
        Ok(prepared) => prepared,
        Err(e) => return Some(e),
    };
    let first = module_pairs(&prepared).err()?;
    match confine_to_procedures(&prepared, first) {
        Ok((blanked, _)) => module_pairs(&blanked).err(),
        Err(e) => Some(e),
    }
}

/// Whether a module's text is in the language's grammar, but for procedures that fail when
/// they run: a class module that is not (`Implements`, `Event` at module level …) is left
/// out of the project rather than failing every module joined with it.
pub(super) fn in_grammar(src: &str) -> bool {
    grammar_error(src).is_none()
}

/// A procedure the grammar refused: the byte range of its first line, and the error.
type Confined = (Range<usize>, ParseError);

/// Module `src` with the body of each procedure the grammar refuses blanked (a space for each
/// byte but line ends, so every offset and line stays, as `conditional::blank` leaves a
/// skipped branch), and the grammar's error for each, by
/// the byte range of the procedure's first line: VBA compiles a procedure when it first runs,
/// so a line ncsheet cannot read fails its procedure when called, not the whole module and
/// every macro beside it. `first`: the grammar's first error in the whole module; `Err` it
/// where it is in no procedure's body or `End` line (a module-level line, a procedure's first
/// line, a missing `End Sub`), or the error of a procedure whose first line is what fails.
/// Each procedure from the one `first` is in on is read alone, once, so that the work stays
/// that of reading the module twice however many procedures fail; the caller reads the
/// blanked module, which may still fail where the trouble was not the procedure's own.
fn confine_to_procedures(src: &str, first: ParseError) -> Res<(String, Vec<Confined>)> {
    let procedures = procedures_by_line(src);
    let Some(from) = procedures.iter().position(|p| p.confines(first.offset)) else { return Err(first) };
    let mut text = src.as_bytes().to_vec();
    let mut confined: Vec<Confined> = Vec::new();
    for p in &procedures[from..] {
        let Err(mut error) = module_pairs(&src[p.whole.clone()]) else { continue };
        error.offset += p.whole.start;
        if !p.confines(error.offset) {
            return Err(error);
        }
        // Each line of the body made spaces as a skipped `#If` branch is, its end kept.
        for line in line_ranges(&src[p.body.clone()]) {
            let code = src[p.body.start + line.start..p.body.start + line.end].trim_end_matches(['\r', '\n']);
            let at = p.body.start + line.start;
            super::conditional::blank(&mut text[at..at + code.len()]);
        }
        confined.push((p.head.clone(), error));
    }
    Ok((String::from_utf8(text).expect("whole lines blanked"), confined))
}

/// A procedure of a module as its lines show it, by byte ranges: its first line, its body
/// (the lines after its first line, and those that line continues on, up to its `End` line),
/// its `End` line, and the whole from its first line through its `End` line.
struct ProcedureLines {
    head: Range<usize>,
    body: Range<usize>,
    end: Range<usize>,
    whole: Range<usize>,
}

impl ProcedureLines {
    /// An error at byte `at` is the procedure's own, set aside with its body: in the body, or
    /// on the `End` line where a block left open is found.
    fn confines(&self, at: usize) -> bool {
        self.body.start <= at && at <= self.end.end
    }
}

/// The procedures of module `src` that end with an `End` line of their own, found by their
/// first and last lines alone (no grammar): one written on one line is not among them, nor
/// one whose `End` line is missing.
fn procedures_by_line(src: &str) -> Vec<ProcedureLines> {
    let lines: Vec<Range<usize>> = line_ranges(src).collect();
    let line = |k: usize| &src[lines[k].clone()];
    let mut out = Vec::new();
    let mut k = 0;
    while k < lines.len() {
        if !is_procedure_head(line(k)) || ends_on_its_line(line(k)) {
            k += 1;
            continue;
        }
        let mut last = k;
        while line(last).trim_end().ends_with(" _") && last + 1 < lines.len() {
            last += 1;
        }
        match (last + 1..lines.len()).find(|&m| is_procedure_end(line(m)) || is_procedure_head(line(m))) {
            Some(m) if is_procedure_end(line(m)) => {
                let (head, end) = (lines[k].clone(), lines[m].clone());
                out.push(ProcedureLines { body: lines[last].end..end.start, whole: head.start..end.end, head, end });
                k = m + 1;
            }
            Some(m) => k = m,
            None => break,
        }
    }
    out
}

/// A procedure written on one line: `Property Get X(): X = m: End Property`.
fn ends_on_its_line(line: &str) -> bool {
    let lower = line.trim_end().to_ascii_lowercase();
    lower.contains(':') && ["end sub", "end function", "end property"].iter().any(|e| lower.ends_with(e))
}

/// The byte ranges of `src`'s lines, each with its line end.
fn line_ranges(src: &str) -> impl Iterator<Item = Range<usize>> + '_ {
    let mut from = 0;
    src.split_inclusive('\n').map(move |l| {
        let range = from..from + l.len();
        from = range.end;
        range
    })
}

/// `[Public|Private|Friend|Global] [Static] Sub|Function|Property Get|Let|Set name…`.
fn is_procedure_head(line: &str) -> bool {
    let mut words = line.split_whitespace().map(str::to_ascii_lowercase).peekable();
    words.next_if(|w| matches!(w.as_str(), "public" | "private" | "friend" | "global"));
    words.next_if(|w| w == "static");
    match words.next().as_deref() {
        Some("sub" | "function") => words.next().is_some(),
        Some("property") => words.next().is_some_and(|w| matches!(w.as_str(), "get" | "let" | "set")),
        _ => false,
    }
}

/// `End Sub`, `End Function`, `End Property`, alone on their line but for a comment.
fn is_procedure_end(line: &str) -> bool {
    let mut words = line.split_whitespace().map(str::to_ascii_lowercase);
    words.next().as_deref() == Some("end")
        && words.next().is_some_and(|w| matches!(w.as_str(), "sub" | "function" | "property"))
        && words.next().is_none_or(|w| w.starts_with('\''))
}

fn from_pest(err: pest::error::Error<Rule>) -> ParseError {
    let stray = stray_closer(&err);
    let mut error = from_pest_with(err, expected);
    if let Some(message) = stray {
        error.message = message.to_string();
    }
    error
}

/// VBA's compile error for a block's closing keyword where no such block is open (`End If`
/// after a one-line `If`): the VBA reference's "End If without block If", "Next without
/// For" …, rather than the closer some other open block wants.
fn stray_closer(err: &pest::error::Error<Rule>) -> Option<&'static str> {
    let pest::error::ErrorVariant::ParsingError { positives, .. } = &err.variant else { return None };
    let (pest::error::LineColLocation::Pos((_, col)) | pest::error::LineColLocation::Span((_, col), _)) = err.line_col;
    let rest: String = err.line().chars().skip(col.saturating_sub(1)).collect::<String>().to_ascii_lowercase();
    let words: Vec<&str> = rest.split(|c: char| !c.is_ascii_alphanumeric() && c != '_').collect();
    let (closer, message) = match words.as_slice() {
        ["end", "if", ..] => (Rule::k_end_if, "End If without block If"),
        ["end", "select", ..] => (Rule::k_end_select, "End Select without Select Case"),
        ["end", "with", ..] => (Rule::k_end_with, "End With without With"),
        ["next", ..] => (Rule::k_next, "Next without For"),
        ["loop", ..] => (Rule::k_loop, "Loop without Do"),
        ["wend", ..] => (Rule::k_wend, "Wend without While"),
        _ => return None,
    };
    (!positives.contains(&closer)).then_some(message)
}

/// What the parser wanted, in the words of the language: the closing keyword when one is
/// possible (the usual mistake), else the kinds of thing that could follow.
fn expected(positives: &[Rule]) -> String {
    let closers: Vec<&str> = positives.iter().filter_map(|r| closer(*r)).collect();
    if let Some(first) = closers.first() {
        let mut all = closers.clone();
        all.dedup();
        return if all.len() == 1 { format!("expected {first}") } else { format!("expected {}", all.join(" or ")) };
    }
    expected_kinds(positives, describe, "this is not a statement or expression the macro language knows", "")
}

fn closer(rule: Rule) -> Option<&'static str> {
    Some(match rule {
        Rule::k_end_if => "End If",
        Rule::k_end_sub => "End Sub",
        Rule::k_end_function => "End Function",
        Rule::k_end_property => "End Property",
        Rule::k_end_select => "End Select",
        Rule::k_end_with => "End With",
        Rule::k_next => "Next",
        Rule::k_loop => "Loop",
        Rule::k_wend => "Wend",
        Rule::k_then => "Then",
        Rule::k_to => "To",
        Rule::k_in => "In",
        _ => return None,
    })
}

fn describe(rule: Rule) -> &'static str {
    match rule {
        Rule::vexpr
        | Rule::vparen
        | Rule::number
        | Rule::string
        | Rule::boolean
        | Rule::path
        | Rule::bracket
        | Rule::bracket_path
        | Rule::date_lit
        | Rule::radix_lit
        | Rule::typed_number
        | Rule::path_is
        | Rule::type_of
        | Rule::k_typeof
        | Rule::new_object
        | Rule::k_new
        | Rule::vneg
        | Rule::vplus
        | Rule::not_op => "a value",
        Rule::ident | Rule::member_name | Rule::link | Rule::member => "a name",
        Rule::EOI | Rule::eol => "the end of the line",
        Rule::sub_def | Rule::function_def | Rule::k_sub | Rule::k_function => "Sub or Function",
        Rule::eq => "an operator",
        _ if is_operator(rule) => "an operator",
        _ => "a statement",
    }
}

/// What a call of a procedure is checked against.
pub(super) struct Signature {
    pub(super) name: Rc<str>,
    pub(super) kind: ProcKind,
    pub(super) params: Vec<Rc<str>>,
    /// How many parameters come before the first Optional one.
    pub(super) required: usize,
    /// The last parameter is a `ParamArray`: the call may give any number of arguments more.
    pub(super) param_array: bool,
    /// The module of the project it is in (`Module::parts`), and whether other modules see it.
    pub(super) part: usize,
    pub(super) public: bool,
    pub(super) property: Option<PropertyKind>,
    /// How each parameter is passed, for the ByRef check of a call (`by_ref.rs`).
    pub(super) passing: Vec<super::by_ref::Passing>,
}

/// What the parser knows while it builds one procedure.
#[derive(Default)]
pub(super) struct Scope {
    /// The Function being built: its name is its result variable.
    pub(super) function: Option<Rc<str>>,
    /// Declared or assigned names, lower case.
    pub(super) vars: std::collections::HashSet<String>,
    /// `Static Function`, `Static Sub`: every `Dim` of the body is `Static` ([MS-VBAL] 5.3.1.2).
    pub(super) all_static: bool,
    /// The body's labels so far, lower case, in any of its blocks: one name labels one line
    /// of the procedure ([MS-VBAL] 5.4.1.1; VBA's compile error "Duplicate label").
    pub(super) labels: std::collections::HashSet<String>,
    /// The body's line-number labels so far: (source line, number).
    pub(super) line_numbers: Vec<(u32, u32)>,
    /// The procedure's parameters and declared variables by lower-case name (`by_ref.rs`).
    pub(super) declarations: std::collections::HashMap<String, super::by_ref::Declaration>,
}

pub(super) struct Build<'s> {
    src: &'s str,
    sheets: &'s dyn Fn(&str) -> Option<SheetId>,
    /// Objects of this run besides the language's own (code names, `me`), lower case.
    pub(super) objects: &'s [String],
    /// Every procedure's signature, by index.
    pub(super) procs: Vec<Signature>,
    /// Each procedure's index by its name in ASCII lower case: a module of many procedures
    /// is read in time proportional to its size.
    pub(super) proc_names: std::collections::HashMap<String, Vec<usize>>,
    /// The project's modules, when the source joins several (`Module::parts`), and the one
    /// whose procedure is being built.
    pub(super) parts: Vec<Part>,
    pub(super) current_part: Cell<usize>,
    /// The module-level names (variables, constants, Enum members) by lower-case name, with
    /// the modules declaring them.
    pub(super) globals: RefCell<std::collections::HashMap<String, Vec<Owner>>>,
    pub(super) scope: RefCell<Scope>,
    pub(super) nodes: RefCell<Vec<Node>>,
    /// Each module's variables by its place in `parts` and lower-case name (`by_ref.rs`).
    pub(super) module_declarations: RefCell<std::collections::HashMap<(usize, String), super::by_ref::Declaration>>,
    /// The modules' `DefLng A-Z` directives (`deftype.rs`), in order.
    pub(super) implicit_types: RefCell<Vec<super::deftype::ImplicitType>>,
    /// The procedure's variables declared by their first use with a Def type (`deftype.rs`).
    pub(super) implicit_vars: RefCell<Vec<VarDecl>>,
    /// Each module's `Option Base`/`Option Compare`/`Option Explicit`, by its place in `parts`.
    options: RefCell<Vec<super::ast::ModuleOptions>>,
    /// The index of each of the module's Types, by its name in lower case (the first of a
    /// name): looked up at every `As`, so a module of 50,000 Types was quadratic.
    types: RefCell<std::collections::HashMap<String, usize>>,
    /// The project's Enums: each one's name and its members' names.
    pub(super) enums: Vec<(Rc<str>, Vec<Rc<str>>)>,
    /// Module-level declarations are being built: they declare globals.
    building_globals: Cell<bool>,
    /// The With blocks around the statement being built, innermost last: what each one's
    /// object is, for the members the parser resolves itself (`resolve.rs`).
    pub(super) with_subjects: RefCell<Vec<super::resolve::WithSubject>>,
    /// The values of the constants declared so far whose value is a whole number (a literal,
    /// another such constant, or `+ - *` of them), by the module declaring them (its place in
    /// `parts`) and lower-case name: a `String * W` reads W's, its own module's first.
    whole_consts: RefCell<std::collections::HashMap<(usize, String), f64>>,
    /// The names of the module's `Declare`d DLL procedures, lower case.
    pub(super) declared: std::collections::HashSet<String>,
    /// The variables every `Set` of the project sets to Excel's WorksheetFunction object:
    /// `wf.Max(…)` is `WorksheetFunction.Max(…)` (`resolve.rs`, `sheet_function_aliases`).
    pub(super) sheet_function_vars: std::collections::HashSet<String>,
    /// The run has files (`files.rs`): file statements and functions are built, not refused.
    pub(super) files: bool,
    lines: Lines,
}

pub(super) fn start(pair: &Pair<Rule>) -> usize {
    pair.as_span().start()
}

pub(super) fn find<'i>(kids: &[Pair<'i, Rule>], rule: Rule) -> Option<Pair<'i, Rule>> {
    kids.iter().find(|p| p.as_rule() == rule).cloned()
}

fn all<'i>(kids: &[Pair<'i, Rule>], rule: Rule) -> Vec<Pair<'i, Rule>> {
    kids.iter().filter(|p| p.as_rule() == rule).cloned().collect()
}

pub(super) fn kids<'i>(pair: &Pair<'i, Rule>) -> Vec<Pair<'i, Rule>> {
    pair.clone().into_inner().collect()
}

/// An `Enum`'s name and its members' names.
fn enum_names(pair: &Pair<Rule>) -> (Rc<str>, Vec<Rc<str>>) {
    let k = kids(pair);
    let members = all(&k, Rule::enum_member).iter().map(|m| enum_member_name(&kids(m))).collect();
    (name_of(&find(&k, Rule::ident).expect("enum name")), members)
}

/// The module declaring a module-level name, and whether the project's other modules see it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Owner {
    pub(super) part: usize,
    pub(super) public: bool,
}

/// A module-level declaration other modules see: `Public` or `Global` variables and
/// constants, and Enums unless `Private` ("Understanding scope and visibility": module-level
/// `Dim`, `Private` and plain `Const` are private to their module).
fn declared_public(item: &Pair<Rule>) -> bool {
    let first = item.as_str().split_whitespace().next().unwrap_or_default().to_ascii_lowercase();
    match item.as_rule() {
        Rule::enum_def => first != "private",
        _ => first == "public" || first == "global",
    }
}

/// An Enum member's name: a plain name, or the text of a `[_First]` without its brackets.
fn enum_member_name(kids: &[Pair<Rule>]) -> Rc<str> {
    match find(kids, Rule::ident) {
        Some(name) => name_of(&name),
        None => unbracketed(find(kids, Rule::foreign_name).expect("member name").as_str()).into(),
    }
}

/// `[_First]` is the name `_First` ([MS-VBAL] 3.3.5.3).
pub(super) fn unbracketed(name: &str) -> &str {
    name.strip_prefix('[').and_then(|n| n.strip_suffix(']')).unwrap_or(name)
}

fn name_of(pair: &Pair<Rule>) -> Rc<str> {
    pair.as_str().into()
}

/// A declared name without its type character: `s$` declares `s` ([MS-VBAL] 3.3.5.3).
fn decl_name(kids: &[Pair<Rule>]) -> Option<Rc<str>> {
    find(kids, Rule::ident).map(|n| n.as_str().trim_end_matches('$').into())
}

/// The type a declared name's type character gives ([MS-VBAL] 3.3.5.3, "Type characters"):
/// `I%` Integer, `N&` Long, `L^` LongLong, `c@` Currency, `f!` Single, `x#` Double, `s$` String.
fn type_char_ty(kids: &[Pair<Rule>]) -> Option<Ty> {
    let mark = match find(kids, Rule::type_char) {
        Some(c) => c.as_str().to_string(),
        None if find(kids, Rule::ident)?.as_str().ends_with('$') => "$".to_string(),
        None => return None,
    };
    Some(match mark.as_str() {
        "%" => ty_named("integer"),
        "&" => ty_named("long"),
        "^" => ty_named("longlong"),
        "@" => ty_named("currency"),
        "!" => ty_named("single"),
        "#" => ty_named("double"),
        _ => ty_named("string"),
    })
}

impl<'s> Build<'s> {
    fn new(
        src: &'s str,
        sheets: &'s dyn Fn(&str) -> Option<SheetId>,
        items: &[Pair<Rule>],
        parts: &[Part],
    ) -> Res<Build<'s>> {
        let b = Build {
            src,
            sheets,
            objects: &[],
            procs: Vec::new(),
            proc_names: std::collections::HashMap::new(),
            parts: parts.to_vec(),
            current_part: Cell::new(0),
            globals: RefCell::new(Default::default()),
            scope: RefCell::new(Scope::default()),
            nodes: RefCell::new(Vec::new()),
            module_declarations: RefCell::new(Default::default()),
            implicit_types: RefCell::new(Vec::new()),
            implicit_vars: RefCell::new(Vec::new()),
            options: RefCell::new(Vec::new()),
            building_globals: Cell::new(false),
            with_subjects: RefCell::new(Vec::new()),
            whole_consts: RefCell::new(Default::default()),
            declared: Default::default(),
            sheet_function_vars: Default::default(),
            files: false,
            types: RefCell::new(std::collections::HashMap::new()),
            enums: items.iter().filter(|i| i.as_rule() == Rule::enum_def).map(enum_names).collect(),
            lines: Lines::new(src),
        };
        let mut procs: Vec<Signature> = Vec::new();
        let mut proc_names: std::collections::HashMap<String, Vec<usize>> = std::collections::HashMap::new();
        for item in items {
            if !matches!(item.as_rule(), Rule::sub_def | Rule::function_def | Rule::property_def) {
                continue;
            }
            let k = kids(item);
            let name_pair = find(&k, Rule::ident).expect("procedure name");
            let name = decl_name(&k).expect("procedure name");
            let part = b.part_at(start(item));
            let property = property_kind(item);
            let same_name = proc_names.entry(name.to_ascii_lowercase()).or_default();
            // A Property Get and its Let or Set share a name ([MS-VBAL] 5.3.1.4).
            let clash =
                |i: usize| procs[i].part == part && (procs[i].property.is_none() || procs[i].property == property);
            if same_name.iter().any(|&i| clash(i)) {
                return Err(b.error_at(&name_pair, format!("{name} is defined twice")));
            }
            same_name.push(procs.len());
            let public = find(&k, Rule::scope).is_none_or(|s| !s.as_str().eq_ignore_ascii_case("Private"));
            let kind = proc_kind(item);
            let params: Vec<Pair<Rule>> =
                find(&k, Rule::param_list).map(|l| all(&kids(&l), Rule::param)).unwrap_or_default();
            let names = params.iter().map(|p| decl_name(&kids(p)).expect("param name")).collect();
            let param_array = params.last().is_some_and(|p| find(&kids(p), Rule::k_paramarray).is_some());
            let required = params
                .iter()
                .filter(|p| find(&kids(p), Rule::k_optional).is_none() && find(&kids(p), Rule::vexpr).is_none())
                .count()
                - usize::from(param_array);
            let passing = params.iter().map(|p| super::by_ref::passing(p, type_char_ty(&kids(p)))).collect();
            procs.push(Signature { name, kind, params: names, required, param_array, part, public, property, passing });
        }
        Ok(Build { procs, proc_names, ..b })
    }

    /// The module-level variables, constants and Enum members of the project, each with its
    /// module, known before any procedure is built: a procedure of the first module uses a
    /// `Public Const PI` or an Enum member of a module after it ("Understanding scope and
    /// visibility": a Public module-level name is available to all procedures in all modules).
    /// A class module's variables are its objects' own, declared where the class is built.
    fn declare_project_globals(&self, items: &[Pair<Rule>]) {
        for item in items {
            let part = self.part_at(start(item));
            let names: Vec<Rc<str>> = match item.as_rule() {
                Rule::enum_def => enum_names(item).1,
                Rule::dim_stmt | Rule::const_stmt if self.standard(part) => {
                    let variables = all(&kids(item), Rule::dim_var).into_iter();
                    let constants = all(&kids(item), Rule::const_item).into_iter();
                    variables.chain(constants).filter_map(|n| decl_name(&kids(&n))).collect()
                }
                _ => continue,
            };
            for name in names {
                self.declare_module_name(&name, Owner { part, public: declared_public(item) });
            }
        }
        for (name, _) in super::classes::default_instances(&self.parts) {
            self.declare_module_name(&name, Owner { part: 0, public: true });
        }
    }

    /// The standard modules' module-level constants and every Enum's members, one statement
    /// a constant, each after the constants its value reads (`const_order.rs`): a module's
    /// variables are declared after them at a run, and `String * W` reads W's whole value
    /// wherever W is declared. A constant computed from itself is refused here.
    fn module_constants(&self, items: &[Pair<Rule>]) -> Res<Vec<Stmt>> {
        let mut consts = Vec::new();
        for item in items {
            let part = self.part_at(start(item));
            self.current_part.set(part);
            let stmt = match item.as_rule() {
                Rule::enum_def => self.enum_def(item)?,
                Rule::const_stmt if self.standard(part) => {
                    self.building_globals.set(true);
                    let built = self.statement(item.clone());
                    self.building_globals.set(false);
                    built?.expect("a declaration")
                }
                _ => continue,
            };
            let StmtKind::Const(items) = stmt.kind else { unreachable!("constants are Const statements") };
            consts.extend(items.into_iter().map(|(name, ty, value)| ModuleConst { part, name, ty, value }));
        }
        let deps = self.const_dependencies(&consts);
        let order = super::const_order::dependency_order(&deps).map_err(|cycle| ParseError {
            offset: consts[cycle[0]].value.span.start as usize,
            message: self.circular_constants(&consts, &cycle),
        })?;
        let mut slots: Vec<Option<ModuleConst>> = consts.into_iter().map(Some).collect();
        let mut stmts = Vec::with_capacity(slots.len());
        for i in order {
            let c = slots[i].take().expect("each constant once");
            self.current_part.set(c.part);
            let key = (c.part, c.name.to_ascii_lowercase());
            match self.whole_value(&c.value) {
                Some(n) => self.whole_consts.borrow_mut().insert(key, n),
                None => self.whole_consts.borrow_mut().remove(&key),
            };
            let span = self.span(c.value.span.start as usize);
            stmts.push(Stmt { kind: StmtKind::Const(vec![(c.name, c.ty, c.value)]), span });
        }
        Ok(stmts)
    }

    /// Notes that module `owner.part` declares `name` at its level. Each module has its own
    /// ("Understanding scope and visibility"; the interpreter keeps a table per module), so
    /// the same name in two modules is two variables, not a clash.
    fn declare_module_name(&self, name: &str, owner: Owner) {
        let mut globals = self.globals.borrow_mut();
        let owners = globals.entry(name.to_ascii_lowercase()).or_default();
        if !owners.iter().any(|o| o.part == owner.part) {
            owners.push(owner);
        }
    }

    /// A module-level name declared in the module being built (a class module's field too).
    fn declare_own_module_name(&self, name: &str) {
        self.declare_module_name(name, Owner { part: self.current_part.get(), public: false });
    }

    /// The names standard modules declare Public, and the members of a class module's Public
    /// Enum (an Enum is a type of the project, not a field of the class's objects: "Enum
    /// statement", Public "visible to all procedures in all modules"), each with the first
    /// module declaring it, for the interpreter's lookup from other modules
    /// ([`Module::public_names`]).
    fn public_names(&self) -> std::collections::HashMap<Box<str>, usize> {
        let globals = self.globals.borrow();
        let seen_from_outside =
            |name: &str, o: &Owner| o.public && (self.standard(o.part) || self.names_enum_member(name));
        let first_public =
            |name: &str, owners: &Vec<Owner>| owners.iter().find(|o| seen_from_outside(name, o)).map(|o| o.part);
        globals.iter().filter_map(|(name, owners)| Some((name.as_str().into(), first_public(name, owners)?))).collect()
    }

    /// `name` (lower case) is a member of one of the project's Enums.
    fn names_enum_member(&self, name: &str) -> bool {
        self.enums.iter().any(|(_, members)| members.iter().any(|m| m.eq_ignore_ascii_case(name)))
    }

    /// A standard module of the project (not a class module, whose names are its objects').
    pub(super) fn standard(&self, part: usize) -> bool {
        !self.parts.get(part).is_some_and(|p| p.class)
    }

    pub(super) fn error_at(&self, pair: &Pair<Rule>, message: impl Into<String>) -> ParseError {
        ParseError { offset: start(pair), message: message.into() }
    }

    pub(super) fn span(&self, offset: usize) -> Span {
        self.lines.span(self.src, offset)
    }

    /// The module of the project the source at `offset` belongs to.
    fn part_at(&self, offset: usize) -> usize {
        super::ast::part_of_line(&self.parts, self.span(offset).line)
    }

    fn ctx(&self) -> ParseContext<'_> {
        ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: self.sheets }
    }

    pub(super) fn expr(&self, pair: Pair<Rule>) -> Res<Expr> {
        build_expr(pair, &self.ctx(), Some(self))
    }

    pub(super) fn node(&self, node: Node, at: usize, end: usize) -> Expr {
        let mut nodes = self.nodes.borrow_mut();
        nodes.push(node);
        Expr::new(ExprKind::Host(nodes.len() as u32 - 1), ByteSpan { start: at as u32, end: end as u32 })
    }

    // ---- module ----------------------------------------------------------------------

    /// Sets a directive of the module the `Option` statement `pair` is in: it applies to
    /// that module alone ([MS-VBAL] 5.2.1).
    fn set_option(&self, pair: &Pair<Rule>, set: impl FnOnce(&mut super::ast::ModuleOptions)) {
        let part = self.part_at(start(pair));
        let mut options = self.options.borrow_mut();
        if options.len() <= part {
            options.resize(part + 1, super::ast::ModuleOptions::default());
        }
        set(&mut options[part]);
    }

    /// Whether the module being built declares `Option Explicit`: a directive of its own
    /// module only ([MS-VBAL] 5.2.1.3), so a module without it may use undeclared variables
    /// though another module of the project has it.
    pub(super) fn explicit(&self) -> bool {
        self.options.borrow().get(self.current_part.get()).is_some_and(|o| o.explicit)
    }

    fn option(&self, pair: Pair<Rule>) -> Res<()> {
        let k = kids(&pair);
        let words: Vec<String> = all(&k, Rule::option_word).iter().map(|w| w.as_str().to_ascii_lowercase()).collect();
        match words.first().map(String::as_str) {
            Some("explicit") => self.set_option(&pair, |o| o.explicit = true),
            Some("base") => {
                let n = find(&k, Rule::number).map(|n| n.as_str().to_string()).unwrap_or_default();
                match n.as_str() {
                    "0" | "1" => self.set_option(&pair, |o| o.base = n.parse().expect("0 or 1")),
                    _ => return Err(self.error_at(&pair, "Option Base is 0 or 1")),
                }
            }
            // [MS-VBAL] 5.2.1.4: Binary (the default) or Text; Database is Microsoft Access's.
            Some("compare") => match words.get(1).map(String::as_str) {
                Some("binary") => self.set_option(&pair, |o| o.text_compare = false),
                Some("text") => self.set_option(&pair, |o| o.text_compare = true),
                _ => {
                    return Err(
                        self.error_at(&pair, "Option Compare is Binary or Text (Database is Microsoft Access's)")
                    )
                }
            },
            // Private Module is moot: nothing outside the project reaches its names.
            Some("private") => {}
            _ => return Err(self.error_at(&pair, "Option is Explicit, Base 0|1, Compare or Private Module")),
        }
        Ok(())
    }

    /// A procedure, whose constants are its own ("Understanding scope and visibility": a
    /// constant declared in a procedure is visible only within it): the whole constants it
    /// declares are forgotten at its end, so a later procedure's `String * W` reads the
    /// module's W, not another procedure's.
    fn proc(&self, pair: Pair<Rule>) -> Res<Proc> {
        let module_consts = self.whole_consts.borrow().clone();
        let proc = self.proc_within(pair);
        *self.whole_consts.borrow_mut() = module_consts;
        proc
    }

    fn proc_within(&self, pair: Pair<Rule>) -> Res<Proc> {
        let k = kids(&pair);
        let kind = proc_kind(&pair);
        let name = decl_name(&k).expect("procedure name");
        *self.scope.borrow_mut() = Scope {
            all_static: find(&k, Rule::k_static).is_some(),
            function: (kind == ProcKind::Function).then(|| name.clone()),
            vars: if kind == ProcKind::Function { [name.to_ascii_lowercase()].into() } else { Default::default() },
            labels: Default::default(),
            line_numbers: Vec::new(),
            declarations: Default::default(),
        };
        let params = match find(&k, Rule::param_list) {
            Some(list) => all(&kids(&list), Rule::param).into_iter().map(|p| self.param(p)).collect::<Res<Vec<_>>>()?,
            None => Vec::new(),
        };
        self.check_param_array(&k, &params)?;
        // `As Double()` returns an array: the Function's name holds it as a Variant would.
        let returns_array = find(&k, Rule::empty_parens).is_some();
        let as_clause = find(&k, Rule::as_clause);
        as_clause.as_ref().map(|a| self.fixed_length_allowed(a, false)).transpose()?;
        let implicit = || Some(&name).filter(|_| kind == ProcKind::Function).and_then(|n| self.implicit_ty(n));
        let ty =
            as_clause.map(|a| self.ty_of(&a)).or_else(|| type_char_ty(&k)).or_else(implicit).filter(|_| !returns_array);
        self.implicit_vars.borrow_mut().clear();
        let mut body = self.block(find(&k, Rule::block).expect("procedure body"))?;
        self.declare_implicit_vars(&mut body);
        self.check_gotos(&body, &body)?;
        self.check_body_labels(&body, &body)?;
        let public = find(&k, Rule::scope).is_none_or(|s| !s.as_str().eq_ignore_ascii_case("Private"));
        let (part, property) = (self.current_part.get(), property_kind(&pair));
        let mut line_numbers = std::mem::take(&mut self.scope.borrow_mut().line_numbers);
        line_numbers.sort_unstable();
        let line_numbers = line_numbers.into();
        Ok(Proc { name, kind, params, ty, body, span: self.span(start(&pair)), public, part, property, line_numbers })
    }

    fn param(&self, pair: Pair<Rule>) -> Res<Param> {
        let k = kids(&pair);
        let name = decl_name(&k).expect("parameter name");
        self.declare(&name);
        let by_ref = find(&k, Rule::pass_mode).is_none_or(|m| m.as_str().eq_ignore_ascii_case("ByRef"));
        let default = find(&k, Rule::vexpr).map(|e| self.expr(e)).transpose()?;
        find(&k, Rule::as_clause).map(|a| self.fixed_length_allowed(&a, false)).transpose()?;
        let param_array = find(&k, Rule::k_paramarray).is_some();
        let ty = find(&k, Rule::as_clause)
            .map(|a| self.ty_of(&a))
            .or_else(|| type_char_ty(&k))
            .or_else(|| Some(&name).filter(|_| !param_array).and_then(|n| self.implicit_ty(n)));
        let array = find(&k, Rule::empty_parens).is_some();
        self.note_declaration(&name, super::by_ref::Declaration { ty: ty.clone(), array }, false);
        Ok(Param {
            name,
            by_ref,
            optional: find(&k, Rule::k_optional).is_some(),
            default,
            ty,
            array,
            param_array: find(&k, Rule::k_paramarray).is_some(),
        })
    }

    /// [MS-VBAL] 5.3.1.5: a ParamArray is the last parameter, of a list with no Optional
    /// one, and its array is of Variants.
    fn check_param_array(&self, kids_of_proc: &[Pair<Rule>], params: &[Param]) -> Res<()> {
        let Some(at) = params.iter().position(|p| p.param_array) else { return Ok(()) };
        let list = find(kids_of_proc, Rule::param_list).expect("a parameter list holds the ParamArray");
        let why = if at + 1 != params.len() {
            "a ParamArray must be the last parameter"
        } else if params.iter().any(|p| p.optional) {
            "a procedure with a ParamArray cannot have Optional parameters"
        } else if !matches!(params[at].ty, None | Some(Ty::Variant)) {
            "a ParamArray is an array of Variants: declare it As Variant or with no type"
        } else {
            return Ok(());
        };
        Err(self.error_at(&list, format!("{}: {why}", params[at].name)))
    }

    /// Every GoTo names a label of the procedure ("GoTo statement": "any line label … within
    /// the procedure"), of its own block, one around it, or one inside another statement (an
    /// If's arm, a loop's body), where the interpreter goes in.
    fn check_gotos(&self, body: &Block, block: &Block) -> Res<()> {
        for s in &block.stmts {
            match &s.kind {
                StmtKind::GoTo(label) if !has_label(body, label) => {
                    return Err(ParseError {
                        offset: self.offset_of(s.span),
                        message: format!("GoTo {label}: no label {label} in the procedure"),
                    });
                }
                _ => {}
            }
            for inner in inner_blocks(&s.kind) {
                self.check_gotos(body, inner)?;
            }
        }
        Ok(())
    }

    /// `GoSub` names a label of the procedure's body itself: the subroutine runs from there,
    /// outside any loop or If. `On Error GoTo` and `Resume` name any label of the procedure
    /// ("On Error statement": "any line label"), which a GoTo from the failing statement
    /// reaches (`interp.rs` runs a handler inside a block in place).
    fn check_body_labels(&self, body: &Block, block: &Block) -> Res<()> {
        for s in &block.stmts {
            let label = match &s.kind {
                StmtKind::GoSub(l) => Some(l).filter(|l| body.label(l).is_none()),
                StmtKind::OnError(OnError::GoTo(l)) | StmtKind::Resume(Resume::Label(l)) => {
                    Some(l).filter(|l| !has_label(body, l))
                }
                _ => None,
            };
            if let Some(label) = label {
                let message = match &s.kind {
                    StmtKind::GoSub(_) => {
                        format!("no label {label} in the procedure's body (outside its loops and Ifs)")
                    }
                    _ => format!("no label {label} in the procedure"),
                };
                return Err(ParseError { offset: self.offset_of(s.span), message });
            }
            for inner in inner_blocks(&s.kind) {
                self.check_body_labels(body, inner)?;
            }
        }
        Ok(())
    }

    fn offset_of(&self, span: Span) -> usize {
        let line_start = self.lines.starts[span.line as usize - 1];
        self.src[line_start..].char_indices().nth(span.col as usize - 1).map_or(self.src.len(), |(i, _)| line_start + i)
    }

    // ---- statements ------------------------------------------------------------------

    fn block(&self, pair: Pair<Rule>) -> Res<Block> {
        let mut out = Block::default();
        for item in pair.into_inner() {
            match item.as_rule() {
                Rule::label => {
                    let text = item.as_str().trim_end_matches(':');
                    if let Ok(number) = text.parse::<u32>() {
                        let line = self.span(start(&item)).line;
                        self.scope.borrow_mut().line_numbers.push((line, number));
                    }
                    let new_in_procedure = self.scope.borrow_mut().labels.insert(text.to_ascii_lowercase());
                    if !new_in_procedure || !out.add_label(text) {
                        return Err(self.error_at(&item, format!("label {text} is defined twice (Duplicate label)")));
                    }
                }
                _ => {
                    if let Some(s) = self.statement(item)? {
                        for inner in inner_blocks(&s.kind) {
                            out.note_nested(out.stmts.len(), inner);
                        }
                        out.stmts.push(s);
                    }
                }
            }
        }
        Ok(out)
    }

    /// One statement; `None` for comments.
    fn statement(&self, pair: Pair<Rule>) -> Res<Option<Stmt>> {
        let span = self.span(start(&pair));
        let kind = match pair.as_rule() {
            Rule::rem_stmt | Rule::attribute_stmt | Rule::comment_text => return Ok(None),
            Rule::dim_stmt if find(&kids(&pair), Rule::k_static).is_some() => {
                if self.in_module_level() {
                    return Err(self.error_at(&pair, "Static declares a procedure's variable; use Dim here"));
                }
                StmtKind::Static(self.dims(&pair)?)
            }
            Rule::dim_stmt if self.scope.borrow().all_static && !self.in_module_level() => {
                StmtKind::Static(self.dims(&pair)?)
            }
            Rule::dim_stmt => StmtKind::Dim(self.dims(&pair)?),
            Rule::redim_stmt => {
                StmtKind::ReDim { preserve: find(&kids(&pair), Rule::k_preserve).is_some(), vars: self.dims(&pair)? }
            }
            Rule::const_stmt => self.consts(&pair)?,
            Rule::set_stmt | Rule::assign_stmt => self.assign(&pair)?,
            Rule::call_stmt => match self.library_statement(&pair)? {
                Some(kind) => kind,
                None => StmtKind::Call(self.call_stmt(&pair)?),
            },
            Rule::print_stmt => self.print(&pair)?,
            Rule::if_block => self.if_block(&pair)?,
            Rule::if_line => self.if_line(&pair)?,
            Rule::select_block => self.select(&pair)?,
            Rule::for_block => self.for_block(&pair)?,
            Rule::for_each_block => self.for_each(&pair)?,
            Rule::do_block => self.do_block(&pair)?,
            Rule::while_block => {
                let k = kids(&pair);
                let cond = self.expr(find(&k, Rule::vexpr).expect("While condition"))?;
                let body = self.block(find(&k, Rule::block).expect("While body"))?;
                StmtKind::Do { test: Some(LoopTest { until: false, cond }), at_end: false, body }
            }
            Rule::with_block => {
                let k = kids(&pair);
                let object_pair = find(&k, Rule::vexpr).expect("With object");
                let subject = self.with_subject(object_pair.as_str());
                let object = match subject {
                    // Its members are worksheet functions, each resolved to its call: the
                    // object itself has nothing to give at run time.
                    super::resolve::WithSubject::SheetFunctions => Expr::new(
                        ExprKind::Text(object_pair.as_str().trim().into()),
                        ByteSpan { start: start(&object_pair) as u32, end: object_pair.as_span().end() as u32 },
                    ),
                    _ => self.expr(object_pair)?,
                };
                self.with_subjects.borrow_mut().push(subject);
                let body = self.block(find(&k, Rule::block).expect("With body"));
                self.with_subjects.borrow_mut().pop();
                StmtKind::With { object, body: body? }
            }
            Rule::exit_stmt => StmtKind::Exit(self.exit(&pair)?),
            Rule::goto_stmt => {
                let k = kids(&pair);
                let target = find(&k, Rule::ident).or_else(|| find(&k, Rule::line_number)).expect("GoTo label");
                StmtKind::GoTo(name_of(&target))
            }
            Rule::line_number => StmtKind::GoTo(name_of(&pair)),
            Rule::end_stmt => StmtKind::End,
            Rule::gosub_stmt => StmtKind::GoSub(label_of(&pair)),
            Rule::return_stmt => StmtKind::Return,
            Rule::on_error_stmt => StmtKind::OnError(on_error(&pair)),
            Rule::resume_stmt => StmtKind::Resume(match find(&kids(&pair), Rule::k_next) {
                Some(_) => Resume::Next,
                None if kids(&pair).len() > 1 => Resume::Label(label_of(&pair)),
                None => Resume::Retry,
            }),
            Rule::file_stmt => self.file_statement(&pair)?,
            rule => unreachable!("statement {rule:?}"),
        };
        Ok(Some(Stmt { kind, span }))
    }

    fn dims(&self, pair: &Pair<Rule>) -> Res<Vec<VarDecl>> {
        let at_module = self.in_module_level();
        let mut out = Vec::new();
        for var in all(&kids(pair), Rule::dim_var) {
            let k = kids(&var);
            let name = decl_name(&k).expect("variable name");
            let bounds = match find(&k, Rule::dim_bounds) {
                Some(b) => Some(self.bounds(b)?),
                None => None,
            };
            if at_module {
                self.declare_own_module_name(&name);
            } else {
                self.declare(&name);
            }
            let as_clause = find(&k, Rule::as_clause);
            let mut new = None;
            if let Some(a) = &as_clause {
                if let Some(k_new) = find(&kids(a), Rule::k_new) {
                    let class = a.as_str().split_whitespace().last().unwrap_or_default();
                    new = Some(self.class_named(class).ok_or_else(|| self.refuse_new(&k_new, a.as_str()))?);
                }
            }
            as_clause.as_ref().map(|a| self.fixed_length_allowed(a, true)).transpose()?;
            let ty = as_clause.map(|a| self.ty_of(&a)).or_else(|| type_char_ty(&k)).or_else(|| self.implicit_ty(&name));
            if pair.as_rule() != Rule::redim_stmt {
                let declaration = super::by_ref::Declaration { ty: ty.clone(), array: bounds.is_some() };
                self.note_declaration(&name, declaration, at_module);
            }
            out.push(VarDecl { name, ty, bounds, new, span: self.span(start(&var)), field: None, item: None });
        }
        for redim in all(&kids(pair), Rule::redim_field) {
            let names = all(&kids(&redim), Rule::ident);
            let bounds = self.bounds(find(&kids(&redim), Rule::dim_bounds).expect("ReDim's bounds"))?;
            let item = find(&kids(&redim), Rule::redim_item)
                .map(|i| all(&kids(&i), Rule::vexpr).into_iter().map(|e| self.expr(e)).collect::<Res<Vec<Expr>>>())
                .transpose()?;
            out.push(VarDecl {
                item,
                name: name_of(&names[0]),
                ty: None,
                bounds: Some(bounds),
                new: None,
                span: self.span(start(&redim)),
                field: Some(names[1..].iter().map(|n| n.as_str().trim()).collect::<Vec<_>>().join(".").into()),
            });
        }
        Ok(out)
    }

    fn in_module_level(&self) -> bool {
        self.building_globals.get()
    }

    fn bounds(&self, pair: Pair<Rule>) -> Res<Vec<(Option<Expr>, Expr)>> {
        let mut out = Vec::new();
        for bound in all(&kids(&pair), Rule::bound) {
            let mut exprs = all(&kids(&bound), Rule::vexpr).into_iter();
            let first = self.expr(exprs.next().expect("bound"))?;
            out.push(match exprs.next() {
                Some(upper) => (Some(first), self.expr(upper)?),
                None => (None, first),
            });
        }
        Ok(out)
    }

    fn consts(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let at_module = self.in_module_level();
        let mut out = Vec::new();
        for item in all(&kids(pair), Rule::const_item) {
            let k = kids(&item);
            let name = decl_name(&k).expect("constant name");
            let value = self.expr(find(&k, Rule::vexpr).expect("constant value"))?;
            // A constant that is no whole number hides one of its name declared before.
            let key = (self.current_part.get(), name.to_ascii_lowercase());
            match self.whole_value(&value) {
                Some(n) => self.whole_consts.borrow_mut().insert(key, n),
                None => self.whole_consts.borrow_mut().remove(&key),
            };
            find(&k, Rule::as_clause).map(|a| self.fixed_length_allowed(&a, false)).transpose()?;
            let ty = find(&k, Rule::as_clause).map(|a| self.ty_of(&a)).or_else(|| type_char_ty(&k));
            if at_module {
                self.declare_own_module_name(&name);
            } else {
                self.declare(&name);
            }
            out.push((name, ty, value));
        }
        Ok(StmtKind::Const(out))
    }

    fn assign(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let k = kids(pair);
        let set = pair.as_rule() == Rule::set_stmt;
        let value = match find(&k, Rule::new_object) {
            Some(new) => self.new_object(new)?,
            None => self.expr(find(&k, Rule::vexpr).expect("assigned value"))?,
        };
        let target = match (find(&k, Rule::bracket_path), find(&k, Rule::bracket)) {
            (Some(b), _) => match self.bracket_members(&b, None)?.kind {
                ExprKind::Host(id) if matches!(self.nodes.borrow()[id as usize], Node::Members { .. }) => {
                    Target::Node(id)
                }
                _ => return Err(self.not_indexed_here(&b)),
            },
            (None, Some(b)) => match self.bracket(b)?.kind {
                ExprKind::Host(id) => Target::Node(id),
                _ => unreachable!("a bracket is a node"),
            },
            (None, None) => {
                let path = find(&k, Rule::path).expect("assignment target");
                if let Some(mid) = self.mid_statement(&path, &value).transpose().filter(|_| !set) {
                    return mid;
                }
                self.target(path)?
            }
        };
        Ok(StmtKind::Assign { target, value, set })
    }

    /// `New Collection`, `New Class1`: a node that makes the object where it is evaluated.
    fn new_object(&self, new: Pair<Rule>) -> Res<Expr> {
        let class = new.as_str().split_whitespace().last().unwrap_or_default();
        let class = self.class_named(class).ok_or_else(|| self.refuse_new(&new, new.as_str()))?;
        let (at, end) = (start(&new), new.as_span().end());
        Ok(self.node(Node::New { class, span: self.span(at) }, at, end))
    }

    pub(super) fn target(&self, pair: Pair<Rule>) -> Res<Target> {
        // `c(1)(2).Name = x`: a member of an item; `A(1).Arr(2)(3) = x` is refused below.
        // Each reading builds the arguments once: the old second and third readings of the
        // same target doubled the work per level of nested calls in them.
        if let Some(inside) = self.indexed_inside(&pair, false)? {
            return match inside.kind {
                ExprKind::Host(id) if matches!(self.nodes.borrow()[id as usize], Node::Members { .. }) => {
                    Ok(Target::Node(id))
                }
                _ => Err(self.not_indexed_here(&pair)),
            };
        }
        let (path, indexes) = self.path_indexed(&pair)?;
        if !indexes.is_empty() {
            return self.nested_target(pair, path, indexes);
        }
        if !path.with && path.links.len() == 1 {
            let link = &path.links[0];
            let lower = lower_bare(&link.name);
            if FORBIDDEN.contains(&lower.as_str()) && !self.is_var(&link.name) {
                return Err(self.error_at(&pair, refusal(&link.name)));
            }
            match &link.args {
                // `rows = 3` without a Dim is a variable: the sheet's Rows cannot be assigned.
                // A declared variable hides a host object of its name (`Dim nC As Integer` then
                // `nC = 3` beside the Nc object): [MS-VBAL] 5.6.10 looks a simple name up in the
                // procedure, then the module, then the project before any library.
                None if self.is_object(&lower)
                    && !matches!(lower.as_str(), "rows" | "columns")
                    && !self.is_var(&link.name) => {}
                // A variable the procedure or its module declares hides a procedure of that
                // name ([MS-VBAL] 5.6.10: procedure scope first, then module, then project).
                None if self.proc_index(&link.name).is_some()
                    && !self.is_own_function(&link.name)
                    && !self.is_var(&link.name) =>
                {
                    return Err(self.error_at(&pair, format!("{} is a procedure, not a variable", link.name)))
                }
                None => return Ok(Target::Var(self.implicit_named(start(&pair), &link.name)?)),
                Some(args) if self.is_var(&link.name) => {
                    let index = args.iter().map(|a| a.value.clone()).collect();
                    return Ok(Target::Element(link.name.clone(), index));
                }
                Some(_) => {}
            }
        }
        if let Some(target) = self.qualified_target(&path) {
            return Ok(target);
        }
        self.check_path(&pair, &path)?;
        let end = pair.as_span().end();
        match self.node(Node::Path(path), start(&pair), end).kind {
            ExprKind::Host(id) => Ok(Target::Node(id)),
            _ => unreachable!("a node"),
        }
    }

    /// `a(i)(j) = v`: an item of the array an array variable's item holds, read as in an
    /// expression; other indexed results (`f(x)(i)`, `c.Item(k)(i)`) are values, not variables.
    fn nested_target(&self, pair: Pair<Rule>, path: Path, indexes: Vec<Vec<Arg>>) -> Res<Target> {
        let e = self.path_value(&pair, path, indexes, false)?;
        let mut id = match e.kind {
            ExprKind::Host(id) => id,
            _ => return Err(self.not_indexed_here(&pair)),
        };
        let target = id;
        loop {
            match &self.nodes.borrow()[id as usize] {
                Node::Index { base: Expr { kind: ExprKind::Host(inner), .. }, .. } => id = *inner,
                Node::Element { .. } => return Ok(Target::Node(target)),
                // `A(1).Arr(2)(3) = x`: through a variable's Type field (checked when run).
                Node::Path(p) if id != target && p.links.len() > 1 && !p.with && self.is_var(&p.links[0].name) => {
                    return Ok(Target::Node(target))
                }
                _ => return Err(self.not_indexed_here(&pair)),
            }
        }
    }

    fn call_stmt(&self, pair: &Pair<Rule>) -> Res<Expr> {
        let k = kids(pair);
        if let Some(members) = find(&k, Rule::bracket_path) {
            return self.bracket_members(&members, None);
        }
        if let Some(callee) = find(&k, Rule::bracket_callee) {
            let args = self.args(find(&k, Rule::call_args).expect("arguments"))?;
            return self.bracket_members(&callee, Some(args));
        }
        if let Some(path) = find(&k, Rule::path) {
            if find(&k, Rule::k_call).is_none() {
                return self.spaced_call(path);
            }
            return self.path_expr(path, true);
        }
        // `Nc.Line x, z`: the callee's last name takes the arguments.
        let callee = find(&k, Rule::callee).expect("callee");
        let args = self.args(find(&k, Rule::call_args).expect("arguments"))?;
        let mut path = Path { with: false, links: Vec::new(), span: self.span(start(&callee)) };
        // Each link with the index lists after it: `A(1)(2).Add x` calls a member of an item.
        let mut parts = Vec::new();
        for part in callee.clone().into_inner() {
            let end = part.as_span().end();
            match part.as_rule() {
                Rule::with_dot => path.with = true,
                Rule::link | Rule::member => {
                    let (link, indexes) = self.link_indexed(part)?;
                    parts.push((link, indexes, end));
                }
                Rule::member_name | Rule::ident => {
                    let link = Link { name: name_of(&part), args: None, span: self.span(start(&part)) };
                    parts.push((link, Vec::new(), end));
                }
                rule => unreachable!("callee part {rule:?}"),
            }
        }
        parts.last_mut().expect("a name").0.args = Some(args);
        if parts.iter().any(|(_, indexes, _)| !indexes.is_empty()) {
            return Ok(self.chain(&callee, path.with, parts, true)?.expect("an index list before the member called"));
        }
        path.links = parts.into_iter().map(|(link, _, _)| link).collect();
        self.resolve(&callee, path, true, pair.as_span().end())
    }

    /// `Foo (y)` without Call: the parentheses belong to the argument, an expression, so `y`
    /// is passed by value ([MS-VBAL] 5.4.2.2); `Foo(y)` and `Call Foo(y)` pass it by reference.
    fn spaced_call(&self, pair: Pair<Rule>) -> Res<Expr> {
        if let Some(chain) = self.indexed_inside(&pair, true)? {
            return Ok(chain);
        }
        let mut path = self.path_syntax(&pair)?;
        let spaced = pair.as_str().split_once('(').is_some_and(|(name, _)| name.ends_with([' ', '\t']));
        if let ([link], true) = (path.links.as_mut_slice(), spaced) {
            for arg in link.args.iter_mut().flatten().filter(|a| a.value.kind != ExprKind::Missing) {
                let value = std::mem::replace(&mut arg.value, Expr::new(ExprKind::Missing, ByteSpan::default()));
                let span = value.span;
                arg.value = Expr::new(ExprKind::Paren(Box::new(value)), span);
            }
        }
        self.resolve(&pair, path, true, pair.as_span().end())
    }

    fn print(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let mut items = Vec::new();
        for p in pair.clone().into_inner() {
            match p.as_rule() {
                Rule::vexpr => items.push(PrintItem::Value(self.expr(p)?)),
                Rule::print_sep if p.as_str() == ";" => items.push(PrintItem::Join),
                Rule::print_sep => items.push(PrintItem::Zone),
                _ => {}
            }
        }
        Ok(StmtKind::Print(items))
    }

    fn if_block(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let k = kids(pair);
        let mut arms = vec![(
            self.expr(find(&k, Rule::vexpr).expect("If condition"))?,
            self.block(find(&k, Rule::block).expect("If body"))?,
        )];
        for arm in all(&k, Rule::elseif_arm) {
            let ak = kids(&arm);
            arms.push((
                self.expr(find(&ak, Rule::vexpr).expect("ElseIf condition"))?,
                self.block(find(&ak, Rule::block).expect("ElseIf body"))?,
            ));
        }
        let otherwise = match find(&k, Rule::else_arm) {
            Some(e) => Some(self.block(find(&kids(&e), Rule::block).expect("Else body"))?),
            None => None,
        };
        Ok(StmtKind::If { arms, otherwise })
    }

    fn if_line(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let k = kids(pair);
        let cond = self.expr(find(&k, Rule::vexpr).expect("If condition"))?;
        // The part before `Else` is the Then part, the part after it the Else part; either may
        // be missing (`If x Then Else y = 1`, `If x Then y = 1 Else`).
        let mut then = Block::default();
        let mut otherwise = None;
        for kid in k {
            match kid.as_rule() {
                Rule::k_else => otherwise = Some(Block::default()),
                Rule::line_body if otherwise.is_some() => otherwise = Some(self.line_body(kid)?),
                Rule::line_body => then = self.line_body(kid)?,
                _ => {}
            }
        }
        Ok(StmtKind::If { arms: vec![(cond, then)], otherwise })
    }

    fn line_body(&self, pair: Pair<Rule>) -> Res<Block> {
        let mut out = Block::default();
        for p in pair.into_inner() {
            if let Some(s) = self.statement(p)? {
                out.stmts.push(s);
            }
        }
        Ok(out)
    }

    fn select(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let k = kids(pair);
        let subject = self.expr(find(&k, Rule::vexpr).expect("Select subject"))?;
        let mut cases = Vec::new();
        let mut otherwise = None;
        for arm in k.iter().filter(|p| matches!(p.as_rule(), Rule::case_arm | Rule::case_else)) {
            let ak = kids(arm);
            if otherwise.is_some() {
                return Err(self.error_at(arm, "Case Else must be the last Case"));
            }
            let body = self.block(find(&ak, Rule::block).expect("Case body"))?;
            if arm.as_rule() == Rule::case_else {
                otherwise = Some(body);
                continue;
            }
            let mut tests = Vec::new();
            for t in ak.iter().filter(|p| matches!(p.as_rule(), Rule::case_is | Rule::case_range | Rule::case_value)) {
                tests.push(self.case_test(t)?);
            }
            cases.push(Case { tests, body });
        }
        Ok(StmtKind::Select { subject, cases, otherwise })
    }

    fn case_test(&self, pair: &Pair<Rule>) -> Res<CaseTest> {
        let k = kids(pair);
        let mut exprs = all(&k, Rule::vexpr).into_iter();
        let first = self.expr(exprs.next().expect("Case value"))?;
        Ok(match pair.as_rule() {
            Rule::case_range => CaseTest::Range(first, self.expr(exprs.next().expect("Case upper bound"))?),
            Rule::case_is => {
                let op = k.iter().find_map(|p| comparison(p.as_rule())).expect("Case Is operator");
                CaseTest::Is(op, first)
            }
            _ => CaseTest::Value(first),
        })
    }

    fn for_block(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let k = kids(pair);
        let names = all(&k, Rule::ident);
        let var = name_of(&names[0]);
        self.implicit(start(&names[0]), &var)?;
        self.check_next(&names)?;
        let mut exprs = all(&k, Rule::vexpr).into_iter().map(|e| self.expr(e));
        let from = exprs.next().expect("For start")?;
        let to = exprs.next().expect("For end")?;
        let step = exprs.next().transpose()?;
        let body = self.block(find(&k, Rule::block).expect("For body"))?;
        Ok(StmtKind::For { var, from, to, step, body })
    }

    /// `Next j` must close the loop over `j`.
    fn check_next(&self, names: &[Pair<Rule>]) -> Res<()> {
        match names {
            [var, next, ..] if !var.as_str().eq_ignore_ascii_case(next.as_str()) => {
                Err(self.error_at(next, format!("Next {} closes the For loop over {}", next.as_str(), var.as_str())))
            }
            _ => Ok(()),
        }
    }

    fn for_each(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let k = kids(pair);
        let names = all(&k, Rule::ident);
        let var = name_of(&names[0]);
        self.implicit(start(&names[0]), &var)?;
        self.check_next(&names)?;
        let group = self.expr(find(&k, Rule::vexpr).expect("For Each group"))?;
        let body = self.block(find(&k, Rule::block).expect("For Each body"))?;
        Ok(StmtKind::ForEach { var, group, body })
    }

    fn do_block(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let k = kids(pair);
        let mut test = None;
        let mut at_end = false;
        let mut body = None;
        for p in &k {
            match p.as_rule() {
                Rule::block => body = Some(self.block(p.clone())?),
                Rule::loop_cond => {
                    if test.is_some() {
                        return Err(self.error_at(p, "a Do loop has its condition after Do or after Loop, not both"));
                    }
                    at_end = body.is_some();
                    let ck = kids(p);
                    let until = find(&ck, Rule::k_until).is_some();
                    test = Some(LoopTest { until, cond: self.expr(find(&ck, Rule::vexpr).expect("loop condition"))? });
                }
                _ => {}
            }
        }
        Ok(StmtKind::Do { test, at_end, body: body.expect("Do body") })
    }

    fn exit(&self, pair: &Pair<Rule>) -> Res<ExitKind> {
        let what = find(&kids(pair), Rule::exit_kind).expect("Exit kind").as_str().to_ascii_lowercase();
        let in_function = self.scope.borrow().function.is_some();
        Ok(match what.as_str() {
            "for" => ExitKind::For,
            "do" => ExitKind::Do,
            "sub" if !in_function => ExitKind::Sub,
            "function" if in_function => ExitKind::Function,
            // A Property Get ends as a Function does, a Let or Set as a Sub.
            "property" if in_function => ExitKind::Function,
            "property" => ExitKind::Sub,
            _ => return Err(self.error_at(pair, format!("Exit {what} outside a {what}"))),
        })
    }

    // ---- expressions -------------------------------------------------------------------

    fn bracket(&self, pair: Pair<Rule>) -> Res<Expr> {
        let (at, end) = (start(&pair), pair.as_span().end());
        let inner = find(&kids(&pair), Rule::expr).expect("bracket expression");
        let expr = build_expr(inner, &self.ctx(), None)?;
        Ok(self.node(Node::Evaluate { expr, span: self.span(at) }, at, end))
    }

    /// `[A1].Offset(1, 0).Value`, `[A1:B2].Copy Destination:=[D1]`: the members of what the
    /// bracket gives (a Range, as Evaluate gives one), followed as a path follows its links
    /// ([`Node::Members`]) and indexed where an index list follows one; `args` are those of
    /// a member called as a statement.
    fn bracket_members(&self, pair: &Pair<Rule>, args: Option<Vec<Arg>>) -> Res<Expr> {
        let mut parts = pair.clone().into_inner();
        let mut e = self.bracket(parts.next().expect("the bracket"))?;
        let span = self.span(start(pair));
        let mut links = Vec::new();
        for part in parts {
            let end = part.as_span().end();
            let (link, indexes) = match part.as_rule() {
                Rule::member_name => {
                    (Link { name: name_of(&part), args: None, span: self.span(start(&part)) }, Vec::new())
                }
                _ => self.link_indexed(part)?,
            };
            links.push(link);
            if !indexes.is_empty() {
                let path = Path { with: false, links: std::mem::take(&mut links), span };
                e = self.members(pair, Some(e), path, end)?;
                e = self.indexed(pair, e, indexes, end)?;
            }
        }
        if let (Some(args), Some(last)) = (args, links.last_mut()) {
            last.args = Some(args);
        }
        match links.is_empty() {
            true => Ok(e),
            false => self.members(pair, Some(e), Path { with: false, links, span }, pair.as_span().end()),
        }
    }

    /// `Stop`, `Randomize [seed]`, `Erase a, b` and `Error n`: statements of VBA's library that
    /// look like calls, unless the macro has a variable or procedure of that name. `Error 13`
    /// is the Error statement, which raises the error ([MS-VBAL] 5.4.4.3), not a call of the
    /// Error function, which only names it.
    fn library_statement(&self, pair: &Pair<Rule>) -> Res<Option<StmtKind>> {
        let k = kids(pair);
        let word: String =
            pair.as_str().trim_start().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        let lower = word.to_ascii_lowercase();
        let library = matches!(lower.as_str(), "stop" | "randomize" | "erase" | "error" | "lset" | "rset");
        if !library || find(&k, Rule::k_call).is_some() || self.is_var(&word) || self.proc_index(&word).is_some() {
            return Ok(None);
        }
        let args = match (find(&k, Rule::path), find(&k, Rule::callee), find(&k, Rule::call_args)) {
            (Some(path), _, _) => match self.path_syntax(&path)?.links.as_mut_slice() {
                [link] => link.args.take().unwrap_or_default(),
                _ => return Ok(None),
            },
            (None, Some(callee), Some(args)) if callee.as_str().trim().eq_ignore_ascii_case(&word) => {
                self.args(args)?
            }
            _ => return Ok(None),
        };
        let values: Vec<Expr> = args.into_iter().map(|a| a.value).collect();
        Ok(Some(match (lower.as_str(), values.as_slice()) {
            ("stop", []) => StmtKind::Stop,
            ("randomize", []) => StmtKind::Randomize(None),
            ("randomize", [_]) => StmtKind::Randomize(values.into_iter().next()),
            ("error", [_]) => StmtKind::Error(values.into_iter().next().expect("one argument")),
            ("lset" | "rset", [statement]) => self.aligned_assignment(pair, &lower, statement)?,
            ("erase", [_, ..]) => {
                let mut names = Vec::new();
                for v in &values {
                    match &v.kind {
                        ExprKind::Name(n) => names.push(n.clone()),
                        _ => return Err(self.error_at(pair, "Erase takes array variables: Erase a, b")),
                    }
                }
                StmtKind::Erase(names)
            }
            _ => {
                return Err(self.error_at(
                    pair,
                    format!("{word}: wrong arguments (Stop; Randomize [seed]; Erase array, …; Error number)"),
                ))
            }
        }))
    }

    fn args(&self, pair: Pair<Rule>) -> Res<Vec<Arg>> {
        let mut out = Vec::new();
        for a in all(&kids(&pair), Rule::varg) {
            let k = kids(&a);
            let name = find(&k, Rule::varg_name).and_then(|n| n.into_inner().next()).map(|ident| ident.as_str().into());
            let value = match find(&k, Rule::vexpr) {
                Some(e) => self.expr(e)?,
                None => Expr::new(ExprKind::Missing, ByteSpan { start: start(&a) as u32, end: start(&a) as u32 }),
            };
            out.push(Arg { name, value });
        }
        // `Foo()` has one empty argument slot in the grammar, and no argument (`Foo(Nothing)`
        // has one: the constant's text is there).
        let empty = |a: &Arg| a.value.kind == ExprKind::Missing && a.value.span.start == a.value.span.end;
        if out.len() == 1 && out[0].name.is_none() && empty(&out[0]) {
            out.clear();
        }
        Ok(out)
    }

    /// A link and the index lists after its arguments (`d(k)(i)`: `(i)`).
    pub(super) fn link_indexed(&self, pair: Pair<Rule>) -> Res<(Link, Vec<Vec<Arg>>)> {
        let span = self.span(start(&pair));
        let k = kids(&pair);
        let name = k.iter().find(|p| matches!(p.as_rule(), Rule::ident | Rule::member_name)).expect("link name");
        let args = match find(&k, Rule::call_parens) {
            Some(p) => Some(self.args(p)?),
            None => None,
        };
        let indexes = all(&k, Rule::index_parens).into_iter().map(|p| self.args(p)).collect::<Res<_>>()?;
        Ok((Link { name: name_of(name), args, span }, indexes))
    }

    fn not_indexed_here(&self, pair: &Pair<Rule>) -> ParseError {
        self.error_at(
            pair,
            format!(
                "{}: an item of what a call gives, `f(x)(i)`, is read at the end of an expression, not \
                 assigned, called or followed by a member here; put it in a variable first",
                pair.as_str().trim()
            ),
        )
    }

    pub(super) fn path_syntax(&self, pair: &Pair<Rule>) -> Res<Path> {
        let (path, indexes) = self.path_indexed(pair)?;
        if !indexes.is_empty() {
            return Err(self.not_indexed_here(pair));
        }
        Ok(path)
    }

    /// A path and the index lists after its last link's arguments (`d.Item(k)(i)`).
    pub(super) fn path_indexed(&self, pair: &Pair<Rule>) -> Res<(Path, Vec<Vec<Arg>>)> {
        let mut path = Path { with: false, links: Vec::new(), span: self.span(start(pair)) };
        let mut indexes = Vec::new();
        for part in pair.clone().into_inner() {
            if !indexes.is_empty() {
                // `d(k)(i).Name`: only the end of the path is indexed.
                return Err(self.not_indexed_here(pair));
            }
            match part.as_rule() {
                Rule::with_dot => path.with = true,
                _ => {
                    let (link, more) = self.link_indexed(part)?;
                    path.links.push(link);
                    indexes = more;
                }
            }
        }
        Ok((path, indexes))
    }
}

impl HostPrimaries for Build<'_> {
    fn primary(&self, pair: Pair<Rule>) -> Result<Expr, ParseError> {
        match pair.as_rule() {
            Rule::bracket => self.bracket(pair),
            Rule::bracket_path => self.bracket_members(&pair, None),
            Rule::path => self.path_expr(pair, false),
            Rule::path_is => self.path_is(pair),
            Rule::type_of => self.type_of(pair),
            Rule::new_object => self.new_object(pair),
            Rule::typed_number => self.typed_number(pair),
            Rule::date_lit => {
                let text = pair.as_str().trim_matches('#');
                let serial = date_literal(text).ok_or_else(|| {
                    self.error_at(
                        &pair,
                        format!("#{text}# is not a date: write #month/day/year#, #year-month-day# or #h:mm:ss#"),
                    )
                })?;
                Ok(Expr::new(
                    ExprKind::Number(serial),
                    ByteSpan { start: start(&pair) as u32, end: pair.as_span().end() as u32 },
                ))
            }
            Rule::radix_lit => {
                let value = radix_literal(pair.as_str()).ok_or_else(|| {
                    self.error_at(&pair, format!("{}: overflow (more than its type holds)", pair.as_str()))
                })?;
                Ok(Expr::new(
                    ExprKind::Number(value),
                    ByteSpan { start: start(&pair) as u32, end: pair.as_span().end() as u32 },
                ))
            }
            rule => unreachable!("macro primary {rule:?}"),
        }
    }
}

impl Build<'_> {
    /// A path, or `a Is Nothing` / `a Is b`: a node the interpreter answers True or False.
    fn path_is(&self, pair: Pair<Rule>) -> Res<Expr> {
        let (at, end) = (start(&pair), pair.as_span().end());
        let mut paths = all(&kids(&pair), Rule::path).into_iter();
        let first = paths.next().expect("a path");
        if find(&kids(&pair), Rule::k_is).is_none() {
            return self.path_expr(first, false);
        }
        let object = self.path_expr(first, false)?;
        let other = paths.next().map(|p| self.path_expr(p, false)).transpose()?;
        Ok(self.node(Node::Is { object, other, span: self.span(at) }, at, end))
    }

    /// `TypeOf x Is Type`: a node the interpreter answers by x's object's type.
    fn type_of(&self, pair: Pair<Rule>) -> Res<Expr> {
        let (at, end) = (start(&pair), pair.as_span().end());
        let k = kids(&pair);
        let object = self.path_expr(find(&k, Rule::path).expect("a path"), false)?;
        let ty = find(&k, Rule::type_path).expect("a type").as_str().into();
        Ok(self.node(Node::TypeOf { object, ty, span: self.span(at) }, at, end))
    }

    /// `10#`, `1E10#`, `1!`, `1@`, `32767%`, `100000&`: the number; an Integer or Long
    /// literal must fit its type ([MS-VBAL] 3.3.2, "Overflow" otherwise).
    fn typed_number(&self, pair: Pair<Rule>) -> Res<Expr> {
        let text = pair.as_str();
        let (digits, suffix) = text.split_at(text.len() - 1);
        let value: f64 = digits.parse().map_err(|_| self.error_at(&pair, format!("{text} is not a number")))?;
        let (fits, kind) = match suffix {
            "%" => (value <= f64::from(i16::MAX) && value.fract() == 0.0, "an Integer (% : up to 32767)"),
            "&" => (value <= f64::from(i32::MAX) && value.fract() == 0.0, "a Long (& : up to 2147483647)"),
            // Digits alone are read as the 64-bit integer they write (the interpreter keeps it
            // exact, `longlong.rs`); the expression holds its nearest double.
            "^" if digits.bytes().all(|b| b.is_ascii_digit()) => {
                (digits.parse::<i64>().is_ok(), "a LongLong (^ : up to 9223372036854775807)")
            }
            "^" => (value < LONG_LONG_END && value.fract() == 0.0, "a LongLong (^ : a whole number below 2^63)"),
            "@" => (value.abs() < 922_337_203_685_477.6, "a Currency (@)"),
            "!" => (value <= f64::from(f32::MAX), "a Single (!)"),
            _ => (value.is_finite(), "a Double (#)"),
        };
        if !fits {
            return Err(self.error_at(&pair, format!("{text}: overflow, not {kind}")));
        }
        Ok(Expr::new(
            ExprKind::Number(value),
            ByteSpan { start: start(&pair) as u32, end: pair.as_span().end() as u32 },
        ))
    }
}

/// The procedure a `Declare [PtrSafe] Function|Sub Name Lib …` line declares, lower case.
fn declared_name(line: &str) -> Option<String> {
    let mut words = line.split_whitespace().map(str::to_ascii_lowercase);
    words.find(|w| w == "function" || w == "sub")?;
    words.next().map(|w| w.trim_end_matches('$').to_string())
}

impl Build<'_> {
    /// The signature of this very procedure: its module's, and for a property procedure the
    /// one of its kind, since `Property Get W()` and `Property Let W(v)` share a name but not
    /// their parameters.
    fn signature_of(&self, name: &str, part: usize, property: Option<PropertyKind>) -> &Signature {
        let same_name = self.proc_names.get(&name.to_ascii_lowercase()).expect("signatures first");
        let own = same_name.iter().map(|&i| &self.procs[i]).find(|s| s.part == part && s.property == property);
        own.expect("signatures first")
    }

    /// A procedure whose body does not compile: its signature, and one statement that stops
    /// the run with the compile error where it is, when the procedure is called.
    fn failed_proc(&self, pair: &Pair<Rule>, error: ParseError) -> Proc {
        let k = kids(pair);
        let name = decl_name(&k).expect("procedure name");
        let kind = proc_kind(pair);
        let (part, property) = (self.current_part.get(), property_kind(pair));
        let signature = self.signature_of(&name, part, property);
        let last = signature.params.len().saturating_sub(1);
        let params = (signature.params.iter().enumerate())
            .map(|(i, p)| Param {
                name: p.clone(),
                by_ref: true,
                optional: true,
                default: None,
                ty: None,
                array: false,
                // Takes the arguments the parser let through for it.
                param_array: signature.param_array && i == last,
            })
            .collect();
        let public = find(&k, Rule::scope).is_none_or(|s| !s.as_str().eq_ignore_ascii_case("Private"));
        let failing = Stmt { kind: StmtKind::CompileError(error.message.into()), span: self.span(error.offset) };
        let mut body = Block::default();
        body.stmts.push(failing);
        let line_numbers = Box::default();
        Proc { name, kind, params, ty: None, body, span: self.span(start(pair)), public, part, property, line_numbers }
    }
}

/// The label a `GoSub`, `Resume` or `On Error GoTo` names (its last name or number).
fn label_of(pair: &Pair<Rule>) -> Rc<str> {
    let k = kids(pair);
    let label = k.iter().rev().find(|p| matches!(p.as_rule(), Rule::ident | Rule::line_number)).expect("a label");
    name_of(label)
}

fn on_error(pair: &Pair<Rule>) -> OnError {
    let k = kids(pair);
    if find(&k, Rule::k_resume).is_some() {
        return OnError::ResumeNext;
    }
    match find(&k, Rule::error_off).map(|p| p.as_str().to_string()).as_deref() {
        Some("0") => OnError::Off,
        Some(_) => OnError::Reset,
        None => OnError::GoTo(label_of(pair)),
    }
}

pub(super) fn arity_message(name: &str, min: usize, max: usize, got: usize) -> String {
    if got > max && max >= crate::eval::functions::MANY {
        return format!(
            "{name} takes at most {max} arguments, not {got} (a call's limit, docs/limits.md): build a longer \
             array with ReDim and a loop, or read it from a range"
        );
    }
    let wanted = match (min, max) {
        (a, b) if a == b => format!("{a}"),
        (a, b) if b >= 255 => format!("at least {a}"),
        (a, b) => format!("{a} to {b}"),
    };
    let plural = if wanted == "1" { "" } else { "s" };
    format!("{name} takes {wanted} argument{plural}, not {got}")
}

fn comparison(rule: Rule) -> Option<BinOp> {
    Some(match rule {
        Rule::eq => BinOp::Eq,
        Rule::ne => BinOp::Ne,
        Rule::lt => BinOp::Lt,
        Rule::le => BinOp::Le,
        Rule::gt => BinOp::Gt,
        Rule::ge => BinOp::Ge,
        _ => return None,
    })
}

impl Build<'_> {
    /// The class `New` names: a class module of the project first, then a Collection, a
    /// Dictionary or VBScript's RegExp. A project's own class named `Dictionary` or
    /// `Collection` is the one `New Dictionary` makes ([MS-VBAL] 5.6.10: a simple name binds
    /// in the enclosing project before referenced libraries); `New Scripting.Dictionary`,
    /// qualified by its library, is still the library's.
    fn class_named(&self, name: &str) -> Option<Made> {
        let mut classes = self.parts.iter().filter(|p| p.class);
        classes
            .position(|p| p.name.eq_ignore_ascii_case(name))
            .map(Made::Object)
            .or_else(|| new_class(name).map(Made::Store))
            .or_else(|| super::regexp::new_class(name))
    }

    /// `Dim c As New Class9`, `Set c = New Class9` of a class the project has not: refused.
    fn refuse_new(&self, pair: &Pair<Rule>, text: &str) -> ParseError {
        let class = text.split_whitespace().last().unwrap_or_default();
        self.error_at(
            pair,
            format!(
                "New {class}: no class module of the project has that name (New makes a Collection, a \
                 Dictionary, VBScript's RegExp or an object of one of the project's class modules)"
            ),
        )
    }

    fn ty_of(&self, as_clause: &Pair<Rule>) -> Ty {
        let name = find(&kids(as_clause), Rule::type_name).map(|t| t.as_str().to_string()).unwrap_or_default();
        match (self.type_by_name(&name), self.fixed_length(as_clause)) {
            (Ty::String, Some(n)) => Ty::FixedString(n),
            (ty, _) => ty,
        }
    }

    /// The type an `As` clause's name stands for: a Type of the module, an Enum, a class
    /// module, or one of VBA's and its libraries'.
    pub(super) fn type_by_name(&self, name: &str) -> Ty {
        match self.types.borrow().get(&name.to_ascii_lowercase()) {
            Some(&i) => Ty::Record(i),
            // An Enum's variables are Longs ([MS-VBAL] 5.2.3.4).
            None if self.enums.iter().any(|(e, _)| e.eq_ignore_ascii_case(name)) => Ty::Whole(3),
            // A class module of the project is an object whatever its name looks like
            // (`XlsWriter` is no Excel enum).
            None if self.parts.iter().any(|p| p.class && p.name.eq_ignore_ascii_case(name)) => Ty::Object,
            None => ty_named(&name.to_ascii_lowercase()),
        }
    }

    /// The length of `String * n`, a number from 1 to 65,526 ([MS-VBAL]'s fixed-length
    /// string: `string-length = constant-name / INTEGER`), written as digits or as the name of
    /// a constant declared before it (`Const W = 10` … `String * W`).
    fn fixed_length(&self, as_clause: &Pair<Rule>) -> Option<u32> {
        let star = find(&kids(as_clause), Rule::fixed_length)?;
        let n = match find(&kids(&star), Rule::fixed_digits) {
            Some(digits) => digits.as_str().parse::<f64>().ok()?,
            None => self.whole_const(find(&kids(&star), Rule::ident)?.as_str())?,
        };
        (1.0..=65526.0).contains(&n).then_some(n as u32).filter(|_| n.fract() == 0.0)
    }

    /// The whole value of the constant `name` as the module being built sees it: its own
    /// (the procedure's, else the module's), else the one Public in one other module
    /// ([MS-VBAL] 5.6.10); `Module2.W`, qualified, is Module2's.
    fn whole_const(&self, name: &str) -> Option<f64> {
        let consts = self.whole_consts.borrow();
        if let Some((module, bare)) = name.split_once('.') {
            let part = self.parts.iter().position(|p| p.name.eq_ignore_ascii_case(module))?;
            return consts.get(&(part, bare.to_ascii_lowercase())).copied();
        }
        let lower = name.to_ascii_lowercase();
        let part = self.current_part.get();
        if let Some(&n) = consts.get(&(part, lower.clone())) {
            return Some(n);
        }
        let public = self.public_owners(&lower);
        match public.as_slice() {
            [one] => consts.get(&(*one, lower)).copied(),
            _ => None,
        }
    }

    /// The value of a constant expression of whole numbers: a literal, a constant declared
    /// before with such a value, or `+ - *` and parentheses of them; `None` for any other.
    fn whole_value(&self, e: &Expr) -> Option<f64> {
        let n = match &e.kind {
            ExprKind::Number(n) => *n,
            ExprKind::Paren(inner) => self.whole_value(inner)?,
            ExprKind::Name(name) => self.whole_const(name)?,
            ExprKind::Binary(op @ (BinOp::Add | BinOp::Sub | BinOp::Mul), a, b) => {
                let (x, y) = (self.whole_value(a)?, self.whole_value(b)?);
                match op {
                    BinOp::Add => x + y,
                    BinOp::Sub => x - y,
                    _ => x * y,
                }
            }
            _ => return None,
        };
        (n.fract() == 0.0).then_some(n)
    }

    /// Refuses `* n` where VBA has no fixed-length String: after another type, with a length
    /// that is no number from 1 to 65526 (nor a constant declared before with one), or on a
    /// parameter, a Function or a Const (`allowed` false: only Dim and a Type's fields).
    fn fixed_length_allowed(&self, as_clause: &Pair<Rule>, allowed: bool) -> Res<()> {
        let Some(star) = find(&kids(as_clause), Rule::fixed_length) else { return Ok(()) };
        let name = find(&kids(as_clause), Rule::type_name).map(|t| t.as_str().to_string()).unwrap_or_default();
        let why = if !name.eq_ignore_ascii_case("string") {
            "only a String has a fixed length (String * n)"
        } else if !allowed {
            "a fixed-length String (String * n) is declared with Dim or as a Type's field, not here"
        } else if self.fixed_length(as_clause).is_none() {
            "the length of String * n is a number from 1 to 65526, or the name of a Const declared before it with such a value"
        } else {
            return Ok(());
        };
        Err(self.error_at(&star, why))
    }

    /// `Enum Tool … End Enum`: a Const of type Long per member, the first 0 and each next one
    /// more than the one before unless it is given a value ([MS-VBAL] 5.2.3.4).
    fn enum_def(&self, pair: &Pair<Rule>) -> Res<Stmt> {
        let mut consts = Vec::new();
        let whole = |kind: ExprKind, at: &Pair<Rule>| {
            Expr::new(kind, ByteSpan { start: start(at) as u32, end: at.as_span().end() as u32 })
        };
        // A member without a value is the last one given a value plus how many came since:
        // that number itself, or that member by name plus the count. (Each member as the one
        // before plus 1 made the k-th member's expression k deep: 100,000 members took
        // 5 billion nodes and aborted at the memory cap.)
        let mut given: Result<f64, Rc<str>> = Ok(0.0);
        let mut since = 0.0;
        for member in all(&kids(pair), Rule::enum_member) {
            let k = kids(&member);
            let name = enum_member_name(&k);
            let value = match find(&k, Rule::vexpr) {
                Some(e) => {
                    let value = self.expr(e)?;
                    given = match value.kind {
                        ExprKind::Number(n) => Ok(n),
                        _ => Err(name.clone()),
                    };
                    since = 0.0;
                    value
                }
                None => match &given {
                    Ok(n) => whole(ExprKind::Number(n + since), &member),
                    Err(named) => {
                        let named = Box::new(whole(ExprKind::Name(named.clone()), &member));
                        let count = Box::new(whole(ExprKind::Number(since), &member));
                        whole(ExprKind::Binary(BinOp::Add, named, count), &member)
                    }
                },
            };
            since += 1.0;
            consts.push((name, Some(Ty::Whole(3)), value));
        }
        Ok(Stmt { kind: StmtKind::Const(consts), span: self.span(start(pair)) })
    }

    fn type_def(&self, pair: Pair<Rule>) -> Res<TypeDef> {
        let k = kids(&pair);
        let name = name_of(&find(&k, Rule::ident).expect("type name"));
        let mut fields: Vec<(Rc<str>, Ty)> = Vec::new();
        let mut bounds = Vec::new();
        // The names so far in lower case: a Type of 100,000 fields compared each with all
        // before it (25 s).
        let mut seen = std::collections::HashSet::new();
        let index = self.types.borrow().get(&name.to_ascii_lowercase()).copied();
        for f in all(&k, Rule::type_field) {
            let fk = kids(&f);
            let field = name_of(&find(&fk, Rule::ident).expect("field name"));
            bounds.push(find(&fk, Rule::dim_bounds).map(|b| self.bounds(b)).transpose()?);
            if !seen.insert(field.to_ascii_lowercase()) {
                return Err(self.error_at(&f, format!("{field} is a field of {name} twice")));
            }
            let as_clause = find(&fk, Rule::as_clause).expect("field type");
            self.fixed_length_allowed(&as_clause, true)?;
            let ty = self.ty_of(&as_clause);
            if matches!((&ty, index), (Ty::Record(i), Some(j)) if *i >= j) {
                return Err(self.error_at(&f, format!("{field}: a field's Type must be declared before {name}")));
            }
            fields.push((field, ty));
        }
        Ok(TypeDef { name, fields, bounds })
    }
}

/// The type a declared type's name (lower case) stands for; an unknown name is an object
/// (a class module's, or one of Excel's: Range, Worksheet, Collection …).
pub(super) fn ty_named(name: &str) -> Ty {
    // A library's qualified name is its member's type: `VBA.Collection` an object,
    // `Excel.XlDirection` an enum's Long, `VBA.String` a String.
    let name = name.rsplit('.').next().unwrap_or(name);
    match name {
        "integer" => Ty::Whole(2),
        "long" => Ty::Whole(3),
        "byte" => Ty::Whole(17),
        "longlong" | "longptr" => Ty::Whole(20),
        "double" => Ty::Number(5),
        "single" => Ty::Number(4),
        "currency" => Ty::Number(6),
        "decimal" => Ty::Number(14),
        "string" => Ty::String,
        "boolean" => Ty::Boolean,
        "date" => Ty::Number(DATE_VAR_TYPE),
        "variant" | "any" | "" => Ty::Variant,
        // An enum of VBA's, Excel's or Office's library (`VbCompareMethod`, `XlDirection`,
        // `MsoTriState`): its variables are Longs, as a project's own Enum's are ([MS-VBAL]
        // 5.2.3.4), so `Dim m As VbCompareMethod` starts at 0, not Nothing.
        n if library_enum(n) => Ty::Whole(3),
        // Object, Range, Collection, a class module's name …
        _ => Ty::Object,
    }
}

/// Whether a lower-case type name is one of the libraries' enums. Their names follow the
/// libraries' own prefixes: VBA's `Vb…`, Excel's `Xl…`, Office's `Mso…`; of those prefixes
/// only VBIDE's classes (`VBE`, `VBProject`, `VBComponent`) are objects.
fn library_enum(name: &str) -> bool {
    const VBIDE_CLASSES: [&str; 5] = ["vbe", "vbproject", "vbprojects", "vbcomponent", "vbcomponents"];
    let prefixed = ["vb", "xl", "mso"].iter().any(|p| name.len() > p.len() && name.starts_with(p));
    prefixed && !VBIDE_CLASSES.contains(&name)
}

/// Whether the procedure whose body is `body` has label `name`, at any depth.
fn has_label(body: &Block, name: &str) -> bool {
    body.label(name).is_some() || body.nested_label(name).is_some()
}

/// The blocks nested directly in a statement.
pub fn inner_blocks(kind: &StmtKind) -> Vec<&Block> {
    match kind {
        StmtKind::If { arms, otherwise } => arms.iter().map(|(_, b)| b).chain(otherwise).collect(),
        StmtKind::Select { cases, otherwise, .. } => cases.iter().map(|c| &c.body).chain(otherwise).collect(),
        StmtKind::For { body, .. }
        | StmtKind::ForEach { body, .. }
        | StmtKind::Do { body, .. }
        | StmtKind::With { body, .. } => vec![body],
        _ => Vec::new(),
    }
}

/// `&HFFFF`, `&O777`, `&777`, `&H8000&` as [MS-VBAL] 3.3.2 types them: an Integer when the
/// digits fit 16 bits (so `&HFFFF` is -1), else a Long when they fit 32 (`&HFFFFFFFF` is -1);
/// a `&` suffix makes a Long (`&HFFFF&` is 65535), `%` an Integer, `^` a LongLong of 64 bits.
fn radix_literal(text: &str) -> Option<f64> {
    let body = &text[1..];
    let (body, suffix) = match body.strip_suffix(['%', '&', '^']) {
        Some(b) => (b, body.chars().last()),
        None => (body, None),
    };
    let (digits, radix) = match body.as_bytes().first() {
        Some(b'h' | b'H') => (&body[1..], 16),
        Some(b'o' | b'O') => (&body[1..], 8),
        _ => (body, 8),
    };
    let n = u64::from_str_radix(digits, radix).ok()?;
    if suffix == Some('^') {
        // A LongLong's 64 bits, the top one its sign ([MS-VBAL] 3.3.2).
        return Some(n as i64 as f64);
    }
    let integer = match suffix {
        Some('%') => true,
        Some(_) => false,
        None => n <= 0xFFFF,
    };
    if integer {
        (n <= 0xFFFF).then_some(n as u16 as i16 as f64)
    } else {
        (n <= 0xFFFF_FFFF).then_some(n as u32 as i32 as f64)
    }
}

/// A date literal's serial number, as VBA stores a Date: days since 1899-12-30 and the time
/// of day as a fraction ([MS-VBAL] 3.3.3). The date is month/day/year, or year-month-day when
/// the first number has more than two digits; a two-digit year is 1930–2029; the time is
/// `h[:mm[:ss]]` with an optional AM or PM.
fn date_literal(text: &str) -> Option<f64> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let (date_words, time_words): (Vec<&str>, Vec<&str>) =
        words.iter().partition(|w| !w.contains(':') && !is_meridiem(w) && w.contains(['/', '-']));
    let date = match date_words.as_slice() {
        [] => 0.0,
        [d] => date_part(d)?,
        _ => return None,
    };
    let time = match time_words.as_slice() {
        [] => 0.0,
        words => time_part(words)?,
    };
    (!words.is_empty()).then_some(date + time)
}

fn is_meridiem(word: &str) -> bool {
    word.eq_ignore_ascii_case("AM") || word.eq_ignore_ascii_case("PM")
}

fn date_part(word: &str) -> Option<f64> {
    let parts: Vec<&str> = word.split(['/', '-']).collect();
    let [a, _, c] = parts.as_slice() else { return None };
    let numbers: Vec<i64> = parts.iter().map(|p| p.parse().ok()).collect::<Option<_>>()?;
    let (year, month, day) =
        if a.len() > 2 { (numbers[0], numbers[1], numbers[2]) } else { (numbers[2], numbers[0], numbers[1]) };
    let year = match year {
        0..=29 if c.len() <= 2 || a.len() > 2 => year + 2000,
        30..=99 if c.len() <= 2 || a.len() > 2 => year + 1900,
        _ => year,
    };
    let valid_day = (1..=crate::eval::dates::days_in_month(year, month as u32) as i64).contains(&day);
    if !(100..=9999).contains(&year) || !(1..=12).contains(&month) || !valid_day {
        return None;
    }
    // A VBA Date counts days as the 1900 system does (from 1899-12-30), whatever the workbook's.
    let serial = crate::eval::dates::serial_from_ymd(crate::eval::dates::DateSystem::From1900, year, month, day);
    // Excel counts a 29 February 1900 that VBA does not: before March 1900 VBA is one more.
    Some(if (year, month) < (1900, 3) { serial + 1 } else { serial } as f64)
}

fn time_part(words: &[&str]) -> Option<f64> {
    let (clock, meridiem) = match words {
        [clock] => (*clock, None),
        [clock, m] if is_meridiem(m) => (*clock, Some(m.to_ascii_uppercase())),
        _ => return None,
    };
    let numbers: Vec<u32> = clock.split(':').map(|p| p.parse().ok()).collect::<Option<_>>()?;
    let (mut h, m, s) = match numbers.as_slice() {
        [h] if meridiem.is_some() => (*h, 0, 0),
        [h, m] => (*h, *m, 0),
        [h, m, s] => (*h, *m, *s),
        _ => return None,
    };
    match meridiem.as_deref() {
        Some(_) if !(1..=12).contains(&h) => return None,
        Some("AM") if h == 12 => h = 0,
        Some("PM") if h != 12 => h += 12,
        _ => {}
    }
    if h > 23 || m > 59 || s > 59 {
        return None;
    }
    Some(f64::from(h * 3600 + m * 60 + s) / 86_400.0)
}

/// A Sub, or a Function (a Property Get: it has a value); a Property Let or Set is a Sub.
fn proc_kind(pair: &Pair<Rule>) -> ProcKind {
    match (pair.as_rule(), property_kind(pair)) {
        (Rule::function_def, _) | (_, Some(PropertyKind::Get)) => ProcKind::Function,
        _ => ProcKind::Sub,
    }
}

/// `Property Get|Let|Set`: which one; `None` for a Sub or Function.
fn property_kind(pair: &Pair<Rule>) -> Option<PropertyKind> {
    let kind = find(&kids(pair), Rule::property_kind)?;
    Some(match kind.as_str().to_ascii_lowercase().as_str() {
        "get" => PropertyKind::Get,
        "let" => PropertyKind::Let,
        _ => PropertyKind::Set,
    })
}

/// VBA's compile error for a class module's Public constant, array, fixed-length string or
/// user-defined Type ("Constants, fixed-length strings, arrays, user-defined types, and
/// Declare statements not allowed as Public members of an object module": a class models
/// them with Property procedures). `Public Items() As Double` in a .cls does not compile.
fn refuse_public_in_object_module(stmt: &Stmt, offset: usize) -> Res<()> {
    let what = match &stmt.kind {
        StmtKind::Const(items) => items.first().map(|(n, ..)| format!("the constant {n}")),
        StmtKind::Dim(vars) => vars.iter().find_map(|v| match (&v.bounds, &v.ty) {
            (Some(_), _) => Some(format!("the array {}", v.name)),
            (_, Some(Ty::FixedString(_))) => Some(format!("the fixed-length string {}", v.name)),
            (_, Some(Ty::Record(_))) => Some(format!("{}, of a user-defined type,", v.name)),
            _ => None,
        }),
        _ => None,
    };
    match what {
        Some(what) => Err(ParseError {
            offset,
            message: format!(
                "{what} cannot be a Public member of a class module: Constants, fixed-length strings, arrays, \
                 user-defined types and Declare statements not allowed as Public members of object modules \
                 (VBA's compile error; declare it Private and give it Property procedures)"
            ),
        }),
        None => Ok(()),
    }
}

/// The names a module-level `Dim` or `Const` declares, lower case.
fn declared_names(stmt: &Stmt) -> Vec<String> {
    match &stmt.kind {
        StmtKind::Dim(vars) => vars.iter().map(|v| v.name.to_ascii_lowercase()).collect(),
        StmtKind::Const(items) => items.iter().map(|(n, ..)| n.to_ascii_lowercase()).collect(),
        _ => Vec::new(),
    }
}
