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
//!
//! Finding every match ([`Searches`]) searches again from each match's end, and a search reads
//! on past its match while a thread of higher priority is alive: `.*[^A-Z]|[A-Z]` reads to the
//! text's end for each one-letter match, the crate's documented O(m·n²) for its iterators
//! (32,767 letters: 40 s). Each search of an iteration is charged the bytes it will read,
//! found by stepping the pattern's states as the PikeVM does without their slots
//! ([`Pattern::scan_end`]), and the charges added up meet the same [`MAX_MATCH_WORK`].

use std::fmt;

use regex::{Regex, RegexBuilder};
use regex_automata::nfa::thompson::{self, State, NFA};
use regex_automata::util::primitives::StateID;
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
    /// The bytes of the text, or of the items looked through.
    pub bytes: usize,
    pub of: Searched,
}

/// What work was added up.
#[derive(Debug, Clone, PartialEq)]
pub enum Searched {
    /// One search of one text.
    One,
    /// The searches finding every match in one text ([`Searches`]), refused after this many.
    Matches(usize),
    /// A lookup's searches of this many items, one each (XLOOKUP and XMATCH's match mode 3).
    Items(usize),
}

impl TooMuchWork {
    /// A lookup whose searches of `items` items holding `bytes` bytes came to `work`.
    pub fn lookup(work: u64, items: usize, bytes: usize) -> TooMuchWork {
        TooMuchWork { work, bytes, of: Searched::Items(items) }
    }
}

impl fmt::Display for TooMuchWork {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self.of {
            Searched::One => write!(
                f,
                "matching this pattern against a text of {} bytes is {:.1e} steps of work, more than ncsheet's limit \
                 of {MAX_MATCH_WORK:.0e} for one search (the states the pattern can have active × its capture groups, \
                 per byte); write a simpler pattern or search a shorter text",
                self.bytes, self.work as f64
            ),
            Searched::Matches(matches) => write!(
                f,
                "finding every match of this pattern in a text of {} bytes passed ncsheet's limit of \
                 {MAX_MATCH_WORK:.0e} steps of work after {matches} matches (each search after a match reads on as \
                 far as the pattern could still match, here again and again over the rest of the text); write a \
                 simpler pattern or search a shorter text",
                self.bytes
            ),
            Searched::Items(items) => write!(
                f,
                "searching {items} item{} ({} bytes) with this pattern is {:.1e} steps of work, more than \
                 ncsheet's limit of {MAX_MATCH_WORK:.0e} for one lookup (the states the pattern can have active × its \
                 capture groups, per byte of each item); write a simpler pattern or look through fewer items",
                if items == 1 { "" } else { "s" },
                self.bytes,
                self.work as f64
            ),
        }
    }
}

/// A compiled pattern and what a search with it costs per byte of text.
#[derive(Debug)]
pub struct Pattern {
    pub regex: Regex,
    /// The same pattern's NFA, stepped to find how far a search reads ([`Pattern::scan_end`]).
    nfa: NFA,
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
            return Err(TooMuchWork { work, bytes: text.len(), of: Searched::One });
        }
        Ok(())
    }

    /// The searches of an iteration over `text`, none run yet.
    pub fn searches<'p>(&'p self, text: &'p str) -> Searches<'p> {
        let closure = Closure::new(&self.nfa);
        Searches { pattern: self, text, closure, work: 0, matches: 0, next: 0 }
    }

    /// The last byte a search of `text` from `at` reads (the text's length for its end):
    /// the crate's PikeVM steps the states alive at each byte, starting the pattern afresh at
    /// each byte until it has a match, and stops once none is left or the text ends; a match
    /// drops the threads of lower priority. The same states are stepped here in the same
    /// order (the one NFA compiler, the same syntax) without their capture slots. `None` once
    /// the search would read more than `limit` bytes, before they are stepped.
    fn scan_end(&self, closure: &mut Closure, text: &[u8], at: usize, limit: u64) -> Option<usize> {
        let (nfa, anchored) = (&self.nfa, self.nfa.is_always_start_anchored());
        closure.base = closure.base.saturating_add(text.len() as u64 + 2);
        let (mut current, mut next) = (Vec::new(), Vec::new());
        let mut matched = false;
        let mut pos = at;
        while pos <= text.len() {
            if current.is_empty() && (matched || (anchored && pos > at)) {
                break;
            }
            if (pos - at) as u64 >= limit {
                return None;
            }
            if !matched && (!anchored || pos == at) {
                closure.add(&mut current, nfa.start_anchored(), text, pos);
            }
            matched |= closure.step(&current, &mut next, text, pos);
            std::mem::swap(&mut current, &mut next);
            next.clear();
            pos += 1;
        }
        Some(pos.min(text.len()))
    }
}

/// The states a search has alive at one byte, in the PikeVM's order of priority.
struct Closure<'n> {
    nfa: &'n NFA,
    stack: Vec<StateID>,
    /// For each state, the mark of the byte it was last added at: `base` + the byte + 1, the
    /// base moving past the text's length for each search (0: never).
    seen: Vec<u64>,
    base: u64,
}

impl<'n> Closure<'n> {
    fn new(nfa: &'n NFA) -> Closure<'n> {
        Closure { nfa, stack: Vec::new(), seen: vec![0; nfa.states().len()], base: 0 }
    }

    /// Adds to `into` the states that read a byte or match reached from `from` at byte `at`
    /// without reading one, depth first, the first alternative first, each state once per
    /// byte (a state already reached is reached with a higher priority).
    fn add(&mut self, into: &mut Vec<StateID>, from: StateID, text: &[u8], at: usize) {
        self.stack.push(from);
        while let Some(mut id) = self.stack.pop() {
            loop {
                let mark = self.base + at as u64 + 1;
                if self.seen[id.as_usize()] == mark {
                    break;
                }
                self.seen[id.as_usize()] = mark;
                match self.nfa.state(id) {
                    State::Look { look, next } if self.nfa.look_matcher().matches(*look, text, at) => id = *next,
                    State::Capture { next, .. } => id = *next,
                    State::BinaryUnion { alt1, alt2 } => {
                        self.stack.push(*alt2);
                        id = *alt1;
                    }
                    State::Union { alternates } if !alternates.is_empty() => {
                        self.stack.extend(alternates[1..].iter().rev());
                        id = alternates[0];
                    }
                    State::ByteRange { .. } | State::Sparse(_) | State::Dense(_) | State::Match { .. } => {
                        into.push(id);
                        break;
                    }
                    _ => break,
                }
            }
        }
    }

    /// Steps `current`'s states over the byte at `at` into `next`, in their order, up to the
    /// first that matches (those after it have a lower priority and are dropped): whether one
    /// did.
    fn step(&mut self, current: &[StateID], next: &mut Vec<StateID>, text: &[u8], at: usize) -> bool {
        for &id in current {
            let target = match self.nfa.state(id) {
                State::Match { .. } => return true,
                State::ByteRange { trans } => trans.matches(text, at).then_some(trans.next),
                State::Sparse(sparse) => sparse.matches(text, at),
                State::Dense(dense) => dense.matches(text, at),
                _ => None,
            };
            if let Some(target) = target {
                self.add(next, target, text, at + 1);
            }
        }
        false
    }
}

/// The searches of one iteration over a text (every match of REGEXEXTRACT's mode 1,
/// REGEXREPLACE, a macro's Global Execute and Replace), each charged before it runs the work
/// of the bytes it will read, and refused once the work added up passes [`MAX_MATCH_WORK`].
pub struct Searches<'p> {
    pattern: &'p Pattern,
    text: &'p str,
    closure: Closure<'p>,
    work: u64,
    matches: usize,
    /// Where the next search starts: the last match's end.
    next: usize,
}

impl<'p> Searches<'p> {
    /// The work charged so far.
    pub fn work(&self) -> u64 {
        self.work
    }

    /// Charges a search that starts at byte `at`: the work charged.
    pub fn charge(&mut self, at: usize) -> Result<u64, TooMuchWork> {
        if at > self.text.len() {
            // Past the end (after an empty match at it): no search runs.
            return Ok(0);
        }
        let per_byte = self.pattern.per_byte.max(1);
        let left = MAX_MATCH_WORK.saturating_sub(self.work) / per_byte;
        match self.pattern.scan_end(&mut self.closure, self.text.as_bytes(), at, left) {
            Some(end) => {
                let work = per_byte.saturating_mul((end - at) as u64 + 1);
                self.work = self.work.saturating_add(work);
                Ok(work)
            }
            None => Err(TooMuchWork {
                work: self.work.saturating_add(per_byte.saturating_mul(left)),
                bytes: self.text.len(),
                of: Searched::Matches(self.matches),
            }),
        }
    }

    /// Charges the searches the crate's iterator may run next: one from the last match's
    /// end and, for a pattern that can match empty after a match, one from the next
    /// character (the iterator searches again there when the first finds an empty match at
    /// the last match's end): that second charge, given back by [`Searches::ran`] when the
    /// match found shows the second search did not run.
    fn charge_next(&mut self) -> Result<(usize, u64), TooMuchWork> {
        let at = self.next;
        self.charge(at)?;
        if self.matches == 0 || !self.pattern.nfa.has_empty() {
            return Ok((at, 0));
        }
        let width = self.text[at..].chars().next().map_or(1, char::len_utf8);
        Ok((at, self.charge(at + width)?))
    }

    /// Records what the searches charged from `at` found: a match starting at `at` came from
    /// the first of them, and the second's `provisional` charge is given back.
    fn ran(&mut self, at: usize, provisional: u64, found: Option<(usize, usize)>) {
        if let Some((start, end)) = found {
            self.matches += 1;
            self.next = end;
            if start == at {
                self.work -= provisional;
            }
        }
    }

    /// `matches`, one of the crate's iterators over this text (`find_iter`, `captures_iter`),
    /// each search charged before it runs; `span` gives where an item matched. An `Err`
    /// ends it.
    pub fn charged<'s, T, I, F>(
        &'s mut self,
        mut matches: I,
        span: F,
    ) -> impl Iterator<Item = Result<T, TooMuchWork>> + use<'s, 'p, T, I, F>
    where
        I: Iterator<Item = T> + 's,
        F: Fn(&T) -> (usize, usize) + 's,
    {
        let mut done = false;
        std::iter::from_fn(move || {
            if done {
                return None;
            }
            let (at, provisional) = match self.charge_next() {
                Ok(charged) => charged,
                Err(e) => {
                    done = true;
                    return Some(Err(e));
                }
            };
            let item = matches.next();
            self.ran(at, provisional, item.as_ref().map(&span));
            done = item.is_none();
            item.map(Ok)
        })
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
    Ok(Pattern { regex, nfa, per_byte })
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

    /// The work of finding every match of `pattern` in `text` with the crate's `find_iter`.
    fn iteration_work(pattern: &str, text: &str) -> Result<(u64, usize), TooMuchWork> {
        let pattern = compile(pattern, false).unwrap();
        let mut searches = pattern.searches(text);
        let found = searches.charged(pattern.regex.find_iter(text), |m| (m.start(), m.end()));
        let matches = found.collect::<Result<Vec<_>, _>>()?.len();
        Ok((searches.work() / pattern.per_byte, matches))
    }

    /// `.*[^A-Z]|[A-Z]` over letters: by leftmost-first priority (the `regex` crate's
    /// documented semantics) each one-letter match waits on the first branch, alive to the
    /// text's end, so every search reads the rest of the text: 200 searches that find a letter
    /// and one at the end that finds nothing read 201 + 200 + … + 1 bytes (each search is
    /// charged the bytes it reads and one more, the end).
    #[test]
    fn a_pattern_that_rereads_the_rest_is_charged_every_reading() {
        let (bytes, matches) = iteration_work(".*[^A-Z]|[A-Z]", &"A".repeat(200)).unwrap();
        assert_eq!(matches, 200);
        assert_eq!(bytes, 201 * 202 / 2);
    }

    /// A letter at a time: each search reads its letter and the next byte (a match is seen a
    /// byte late, the PikeVM's delay), so the work grows with the text, not its square.
    #[test]
    fn a_pattern_that_stops_at_its_match_is_charged_linearly() {
        let (bytes, matches) = iteration_work("[A-Z]", &"A".repeat(1000)).unwrap();
        assert_eq!(matches, 1000);
        assert!(bytes <= 3 * 1001, "{bytes}");
        // Lazy: the match has the priority, the longer threads are dropped at once.
        let (bytes, matches) = iteration_work(r"\w+?", &"ab".repeat(500)).unwrap();
        assert_eq!(matches, 1000);
        assert!(bytes <= 3 * 1001, "{bytes}");
    }

    /// Past the limit the iteration stops at the search that would pass it, naming the
    /// matches found before: 3e9 / (this pattern's work per byte) bytes are read by the
    /// first few dozen searches of 32,767 letters.
    #[test]
    fn an_iteration_past_the_limit_is_refused_part_way() {
        let text = "A".repeat(32_767);
        let e = iteration_work(".*[^A-Z]|[A-Z]", &text).unwrap_err();
        let Searched::Matches(found) = e.of else { panic!("{e:?}") };
        let per_byte = compile(".*[^A-Z]|[A-Z]", false).unwrap().per_byte;
        // Search k reads 32,768 - k bytes: the limit falls in the search after `found`.
        let read = |k: u64| (0..k).map(|i| 32_768 - i).sum::<u64>() * per_byte;
        assert!(read(found as u64) <= MAX_MATCH_WORK && read(found as u64 + 1) > MAX_MATCH_WORK, "{found}");
        assert!(e.to_string().contains(&format!("after {found} matches")), "{e}");
    }

    /// After a word, `[^,]*` finds an empty match at its comma, which the crate's iterator
    /// drops (it touches the last match) to search again from the next character: that
    /// search, unseen from outside, reads the next word and is charged too.
    #[test]
    fn the_iterators_search_again_after_an_empty_match_is_charged() {
        let text = "abcdef,".repeat(100);
        let (bytes, matches) = iteration_work("[^,]*", &text).unwrap();
        assert_eq!(matches, 101, "100 words and the empty end");
        assert!(bytes > text.len() as u64, "{bytes}");
    }
}
