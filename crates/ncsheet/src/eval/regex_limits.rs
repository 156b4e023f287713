//! The limits of a regular expression, one place for every user: the cell functions
//! (REGEXTEST, REGEXEXTRACT, REGEXREPLACE, XLOOKUP and XMATCH's match mode 3) and a macro's
//! VBScript RegExp (`vba/regexp.rs`). The `regex` crate runs here without its performance
//! features, so every search is its PikeVM: each byte of the text steps every NFA state that
//! can be active, and each step copies the state's capture slots. A search costs (the states
//! that can be active at once) × (slots + [`STEP_SLOTS`]) per byte; that product, known once
//! the pattern is compiled and the text is read, is refused before the search runs when it
//! passes [`MAX_MATCH_WORK`] (`REGEXTEST(REPT("a",30000),REPT("(a?)",1000)&REPT("a",1000))`
//! ran for 9.6 s). The PikeVM's table of slots (states × slots) is bounded too: 2,000 groups
//! repeated 30 times asked for 15 GB.

use std::fmt;

use regex::{Regex, RegexBuilder};
use regex_automata::nfa::thompson::{self, State, NFA};
use regex_automata::util::syntax;

/// The longest pattern taken, in characters (docs/limits.md).
pub const MAX_PATTERN_CHARS: usize = 10_000;
/// The most memory a compiled pattern may take (the `regex` crate's size limit): a pattern
/// such as `(a{1000}){1000}` is refused instead of built (docs/limits.md).
pub const MAX_COMPILED_BYTES: usize = 8 << 20;
/// The most capture slots the PikeVM's table may hold: states × slots, 16 bytes each, so
/// 64 MiB (docs/limits.md).
pub const MAX_SLOT_TABLE: u64 = 1 << 22;
/// The most work one search may take, in slot copies (docs/limits.md): measured in release
/// (benches/README.md) a slot copy costs about 0.35 ns and a state's step about as much as
/// [`STEP_SLOTS`] of them, so the limit is about a second of the worst pattern's search.
pub const MAX_MATCH_WORK: u64 = 3_000_000_000;
/// What stepping one state costs besides its slots, in slot copies (measured: 17–35 ns a
/// state with two slots, 0.32–0.40 ns a further slot).
pub const STEP_SLOTS: u64 = 100;

/// Why a pattern is not compiled.
#[derive(Debug, Clone, PartialEq)]
pub enum PatternError {
    /// The pattern does not parse: the crate's message.
    Syntax(String),
    /// Longer than [`MAX_PATTERN_CHARS`]: its length.
    TooLong(usize),
    /// Past [`MAX_COMPILED_BYTES`] once compiled.
    TooBig,
    /// The PikeVM's slot table past [`MAX_SLOT_TABLE`]: the states and the slots.
    TooManySlots { states: usize, slots: usize },
}

impl fmt::Display for PatternError {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            PatternError::Syntax(e) => write!(f, "the pattern is beyond what ncsheet's regular expressions take: {e}"),
            PatternError::TooLong(length) => {
                write!(
                    f,
                    "the pattern is {length} characters long; ncsheet takes patterns of up to {MAX_PATTERN_CHARS}"
                )
            }
            PatternError::TooBig => write!(
                f,
                "the pattern would take more than {} MiB once compiled (its repetitions multiply); write it shorter",
                MAX_COMPILED_BYTES >> 20
            ),
            PatternError::TooManySlots { states, slots } => write!(
                f,
                "the pattern's {} capture groups over its {states} states would need {} MiB to match, more than \
                 ncsheet's limit of {} MiB (groups × states); use fewer groups, (?:…) groups capture nothing",
                slots / 2 - 1,
                slot_table_bytes(*states, *slots) >> 20,
                (MAX_SLOT_TABLE * 16) >> 20
            ),
        }
    }
}

/// A search refused before it runs: its work past [`MAX_MATCH_WORK`].
#[derive(Debug, Clone, PartialEq)]
pub struct TooMuchWork {
    pub work: u64,
    pub bytes: usize,
}

impl fmt::Display for TooMuchWork {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "matching this pattern against a text of {} bytes is {:.1e} steps of work, more than ncsheet's limit of \
             {MAX_MATCH_WORK:.0e} for one search (the states the pattern can have active × its capture groups, per \
             byte); write a simpler pattern or search a shorter text",
            self.bytes, self.work as f64
        )
    }
}

/// A compiled pattern and what a search with it costs per byte of text.
#[derive(Debug)]
pub struct Pattern {
    pub regex: Regex,
    per_byte: u64,
}

impl Pattern {
    /// The work of one search of `text` (its bytes and one more, the end).
    pub fn work(&self, text: &str) -> u64 {
        self.per_byte.saturating_mul(text.len() as u64 + 1)
    }

    /// `Ok` when a search of `text` is within [`MAX_MATCH_WORK`].
    pub fn check(&self, text: &str) -> Result<(), TooMuchWork> {
        let work = self.work(text);
        if work > MAX_MATCH_WORK {
            return Err(TooMuchWork { work, bytes: text.len() });
        }
        Ok(())
    }
}

/// `Ok` when `pattern` is within [`MAX_PATTERN_CHARS`] (a macro counts the pattern it was
/// given, before its translation).
pub fn check_length(pattern: &str) -> Result<(), PatternError> {
    let length = pattern.chars().count();
    if length > MAX_PATTERN_CHARS {
        return Err(PatternError::TooLong(length));
    }
    Ok(())
}

/// `pattern` compiled with the `regex` crate's syntax, within every limit above.
pub fn compile(pattern: &str, case_insensitive: bool) -> Result<Pattern, PatternError> {
    check_length(pattern)?;
    compile_translated(pattern, case_insensitive)
}

/// `source` compiled within the limits past the pattern's length, which its caller checked
/// on the pattern it was given (a macro's JScript pattern spells each character out in the
/// `regex` crate's syntax, several times as long).
pub fn compile_translated(source: &str, case_insensitive: bool) -> Result<Pattern, PatternError> {
    let regex =
        RegexBuilder::new(source).case_insensitive(case_insensitive).size_limit(MAX_COMPILED_BYTES).build().map_err(
            |e| match e {
                regex::Error::CompiledTooBig(_) => PatternError::TooBig,
                other => PatternError::Syntax(other.to_string()),
            },
        )?;
    let nfa = thompson::Compiler::new()
        .syntax(syntax::Config::new().case_insensitive(case_insensitive))
        .configure(thompson::Config::new().shrink(false).nfa_size_limit(Some(MAX_COMPILED_BYTES)))
        .build(source)
        .map_err(|_| PatternError::TooBig)?;
    let (states, slots) = (nfa.states().len(), nfa.group_info().slot_len());
    if (states as u64).saturating_mul(slots as u64) > MAX_SLOT_TABLE {
        return Err(PatternError::TooManySlots { states, slots });
    }
    let per_byte = active_states(&nfa).saturating_mul(slots as u64 + STEP_SLOTS);
    Ok(Pattern { regex, per_byte })
}

fn slot_table_bytes(states: usize, slots: usize) -> u64 {
    (states as u64).saturating_mul(slots as u64).saturating_mul(16)
}

/// The byte states' targets that are byte states too.
fn byte_targets(state: &State) -> Vec<usize> {
    match state {
        State::ByteRange { trans } => vec![trans.next.as_usize()],
        State::Sparse(sparse) => sparse.transitions.iter().map(|t| t.next.as_usize()).collect(),
        State::Dense(dense) => dense.transitions.iter().map(|t| t.as_usize()).filter(|&t| t != 0).collect(),
        _ => Vec::new(),
    }
}

fn is_byte_state(state: &State) -> bool {
    matches!(state, State::ByteRange { .. } | State::Sparse(_) | State::Dense(_))
}

/// How many states a search can have active at once, at most: every state but those that
/// read a byte, and of those, for each group linked by byte transitions (a class's UTF-8
/// automaton, a literal's bytes), its entries (states reached otherwise) × its longest path:
/// the transitions of a state never overlap, so a thread entering at a given byte is in one
/// state of the group after each byte. `\w` compiles to about 300 states of which 4 can be
/// active, `(a?){1000}` to 5,000 that can all be.
fn active_states(nfa: &NFA) -> u64 {
    let states = nfa.states();
    let byte: Vec<bool> = states.iter().map(is_byte_state).collect();
    let mut entered = vec![false; states.len()];
    let mut next: Vec<Vec<usize>> = vec![Vec::new(); states.len()];
    for start in [nfa.start_anchored(), nfa.start_unanchored()] {
        entered[start.as_usize()] = true;
    }
    for (i, state) in states.iter().enumerate() {
        if byte[i] {
            for t in byte_targets(state) {
                if byte.get(t) == Some(&true) {
                    next[i].push(t);
                }
            }
        } else {
            for t in epsilon_targets(state) {
                entered[t] = true;
            }
        }
    }
    let others = byte.iter().filter(|b| !**b).count() as u64;
    others.saturating_add(byte_groups_bound(&byte, &next, &entered))
}

/// The states an epsilon state leads to.
fn epsilon_targets(state: &State) -> Vec<usize> {
    match state {
        State::Look { next, .. } | State::Capture { next, .. } => vec![next.as_usize()],
        State::Union { alternates } => alternates.iter().map(|s| s.as_usize()).collect(),
        State::BinaryUnion { alt1, alt2 } => vec![alt1.as_usize(), alt2.as_usize()],
        _ => Vec::new(),
    }
}

/// For each group of byte states linked by byte transitions: the smaller of its size and
/// its entries × (its longest path + 1) (its size when the links make a cycle), summed.
fn byte_groups_bound(byte: &[bool], next: &[Vec<usize>], entered: &[bool]) -> u64 {
    let mut group = linked_groups(next);
    let depth = longest_paths(byte, next);
    // Per group (by its root): size, entries, longest path, whether it holds a cycle.
    let n = byte.len();
    let (mut size, mut entries, mut longest, mut cyclic) =
        (vec![0u64; n], vec![0u64; n], vec![0u64; n], vec![false; n]);
    for i in (0..n).filter(|&i| byte[i]) {
        let g = root(&mut group, i);
        size[g] += 1;
        entries[g] += u64::from(entered[i]);
        match depth[i] {
            Some(d) => longest[g] = longest[g].max(d),
            None => cyclic[g] = true,
        }
    }
    (0..n)
        .filter(|&g| size[g] > 0)
        .map(|g| if cyclic[g] { size[g] } else { size[g].min(entries[g].saturating_mul(longest[g] + 1)) })
        .sum()
}

/// The root of `i`'s group in a union-find forest.
fn root(group: &mut [usize], mut i: usize) -> usize {
    while group[i] != i {
        group[i] = group[group[i]];
        i = group[i];
    }
    i
}

/// The groups of states joined by a link either way, as a union-find forest.
fn linked_groups(next: &[Vec<usize>]) -> Vec<usize> {
    let mut group: Vec<usize> = (0..next.len()).collect();
    for (i, targets) in next.iter().enumerate() {
        for &t in targets {
            let (a, b) = (root(&mut group, i), root(&mut group, t));
            group[a] = b;
        }
    }
    group
}

/// The longest path of links ending at each byte state, in a topological order (Kahn's);
/// `None` for a state on or after a cycle.
fn longest_paths(byte: &[bool], next: &[Vec<usize>]) -> Vec<Option<u64>> {
    let n = byte.len();
    let mut into = vec![0usize; n];
    for &t in next.iter().flatten() {
        into[t] += 1;
    }
    let mut ready: Vec<usize> = (0..n).filter(|&i| byte[i] && into[i] == 0).collect();
    let mut depth = vec![0u64; n];
    let mut done = vec![None; n];
    while let Some(i) = ready.pop() {
        done[i] = Some(depth[i]);
        for &t in &next[i] {
            depth[t] = depth[t].max(depth[i] + 1);
            into[t] -= 1;
            if into[t] == 0 {
                ready.push(t);
            }
        }
    }
    done
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(a?){n}`: every state can be active at once (each `a?` may have taken its `a` or
    /// not), so all count.
    #[test]
    fn optional_chains_count_every_state() {
        let small = compile(&"(?:a?)".repeat(10), false).unwrap();
        let large = compile(&"(?:a?)".repeat(1000), false).unwrap();
        assert!(large.per_byte >= 50 * small.per_byte, "{} vs {}", large.per_byte, small.per_byte);
    }

    /// A Unicode class is hundreds of states of which a thread is in one after each byte
    /// (regex-syntax's UTF-8 automaton: at most 4 bytes a character).
    #[test]
    fn a_class_counts_its_depth_not_its_states() {
        let word = compile(r"\w", false).unwrap();
        let nfa_states = thompson::NFA::new(r"\w").unwrap().states().len() as u64;
        assert!(nfa_states > 100);
        assert!(word.per_byte < 20 * (2 + STEP_SLOTS), "{}", word.per_byte);
    }
}
