//! Which control a program is written for, when the user does not say: from its header
//! (`BEGIN PGM`, Sinumerik's `%_N_…_MPF`), its file's extension (`.h`, `.mpf`, `.ngc`, …) and
//! the words only one control writes (NC31's rapid mark `E`, LinuxCNC's `G7` or `M2`, a Fanuc
//! `O` number or `40.`). The guess carries its reason, for the reader to say what it assumed;
//! [`readers_accepting`] names the dialects that do read a program another refused.

use crate::nc::dialect::{self, Dialect};
use crate::nc::Machine;

/// A dialect assumed for a program, and why.
#[derive(Clone, Debug)]
pub struct Guess {
    pub dialect: &'static dyn Dialect,
    pub reason: String,
}

/// The dialect `text` (from a file ending in `extension`, if any) is most likely written in.
/// A header names its control outright and comes first; then the extension a control gives
/// its programs; then words only one control writes; ISO (Fanuc) when nothing tells.
pub fn guess(text: &str, extension: Option<&str>) -> Guess {
    let found = |dialect: &'static dyn Dialect, reason: String| Guess { dialect, reason };
    if let Some(reason) = header(text) {
        return reason;
    }
    let ext = extension.map(str::to_ascii_lowercase);
    if let Some(dialect) = ext.as_deref().and_then(by_extension) {
        return found(dialect, format!("the extension .{}", ext.unwrap_or_default()));
    }
    if let Some((dialect, word)) = telling_word(text) {
        return found(dialect, format!("the word {word}"));
    }
    found(&dialect::ISO, "nothing in it names another control".into())
}

/// Headers that only one control writes.
fn header(text: &str) -> Option<Guess> {
    let first = text.lines().map(str::trim).find(|l| !l.is_empty())?;
    let upper = first.to_ascii_uppercase();
    let plain = upper.trim_start_matches(|c: char| c.is_ascii_digit()).trim_start();
    if plain.starts_with("BEGIN PGM") {
        return Some(Guess { dialect: &dialect::Heidenhain, reason: "its header BEGIN PGM".into() });
    }
    if upper.starts_with("%_N_") {
        return Some(Guess { dialect: &dialect::SINUMERIK, reason: format!("its header {first}") });
    }
    None
}

/// The extensions controls and their post-processors give programs.
fn by_extension(ext: &str) -> Option<&'static dyn Dialect> {
    match ext {
        "h" => Some(&dialect::Heidenhain),
        "mpf" | "spf" => Some(&dialect::SINUMERIK),
        "ngc" => Some(&dialect::LINUXCNC),
        "nc31" => Some(&dialect::NC31),
        "nc81" => Some(&dialect::NC81),
        _ => None,
    }
}

/// The words only one control writes, in the order they are looked for on a line: the
/// first of them a line holds tells.
const TELLING: [(&dyn Dialect, &str); 8] = [
    (&dialect::SINUMERIK, "DIAMON"),
    (&dialect::SINUMERIK, "DIAMOF"),
    (&dialect::SINUMERIK, "G71"),
    (&dialect::SINUMERIK, "LIMS="),
    (&dialect::LINUXCNC, "G7"),
    (&dialect::LINUXCNC, "G8"),
    (&dialect::LINUXCNC, "M2"),
    (&dialect::LINUXCNC, "G64"),
];

/// The first word in `text` that only one control writes: NC31's rapid mark (a bare `E`),
/// LinuxCNC's diameter modes G7/G8, its end M2 and its O-word subroutines, Sinumerik's
/// DIAMON/DIAMOF and G71 (mm), Fanuc's program number `O1234` and numbers ending in a point.
/// Every line of a program that tells nothing is read: one buffer serves them all (a new
/// upper-cased copy of each line, and a word list, were 16 % of `nc plot`'s time).
fn telling_word(text: &str) -> Option<(&'static dyn Dialect, String)> {
    let mut code = String::new();
    text.lines().find_map(|line| {
        code.clear();
        push_without_comments(line, &mut code);
        code.make_ascii_uppercase();
        telling_in(&code)
    })
}

/// What a line's code (its comments blanked, in capitals) tells, as [`telling_word`] says.
fn telling_in(code: &str) -> Option<(&'static dyn Dialect, String)> {
    let first_telling = code.split(char::is_whitespace).filter_map(telling_index).min();
    if let Some((dialect, word)) = first_telling.map(|i| TELLING[i]) {
        return Some((dialect, word.to_string()));
    }
    if code.trim_start().starts_with("O<") {
        return Some((&dialect::LINUXCNC, "O<…>".into()));
    }
    let mut words = code.split_whitespace();
    let first = words.next();
    // `O100 SUB`: an O-number followed by an O-code keyword is LinuxCNC's subroutine or loop,
    // not Fanuc's program number.
    let second = code.split_whitespace().nth(1);
    if let (Some(o), Some(k)) = (first.filter(|w| is_program_number(w)), second) {
        if super::o_word_keyword_named(k).is_some() {
            return Some((&dialect::LINUXCNC, format!("{o} {k}, an O-code")));
        }
    }
    if words.next_back().or(first) == Some("E") {
        return Some((&dialect::NC31, "E (the rapid mark)".into()));
    }
    if let Some(o) = first.filter(|w| is_program_number(w)) {
        return Some((&dialect::ISO, o.to_string()));
    }
    // `:1234` alone in its block: the program number in ISO code, the colon for the address O
    // (read as O1234, see `fanuc_calls`). A Sinumerik main block `:10` is followed by its words.
    if let Some(colon) = first.filter(|w| is_colon_program_number(w) && second.is_none()) {
        return Some((&dialect::ISO, format!("{colon} (a program number in ISO code)")));
    }
    let ends_in_point = |w: &&str| w.len() > 2 && w.ends_with('.') && w[1..w.len() - 1].parse::<f64>().is_ok();
    if let Some(w) = code.split_whitespace().find(ends_in_point) {
        return Some((&dialect::ISO, format!("{w} (a number ending in its point)")));
    }
    None
}

/// The place in [`TELLING`] of the word `w` is (`G07` is `G7`, `LIMS=3000` is `LIMS=`).
fn telling_index(w: &str) -> Option<usize> {
    let first = *w.as_bytes().first()?;
    TELLING.iter().position(|(_, word)| {
        word.as_bytes()[0] == first
            && (w == *word || (word.ends_with('=') && w.starts_with(word)) || leading_zero_same(w, word))
    })
}

/// `O1234`: a Fanuc program number.
fn is_program_number(word: &str) -> bool {
    word.len() > 1 && word.starts_with('O') && word[1..].chars().all(|c| c.is_ascii_digit())
}

/// `:1234`, a Fanuc program number with the colon ISO code gives the address O.
fn is_colon_program_number(word: &str) -> bool {
    word.strip_prefix(':').is_some_and(|n| (1..=4).contains(&n.len()) && n.chars().all(|c| c.is_ascii_digit()))
}

/// `G07` and `M02` are `G7` and `M2`.
fn leading_zero_same(w: &str, word: &str) -> bool {
    let (Some(a), Some(b)) = (w.chars().next(), word.chars().next()) else { return false };
    if a != b || w.len() < 2 || word.len() < 2 {
        return false;
    }
    match (w[1..].parse::<u32>(), word[1..].parse::<u32>()) {
        (Ok(x), Ok(y)) => x == y && !w[1..].contains('.'),
        _ => false,
    }
}

/// `line` with its `( … )` and `;` comments blanked, pushed onto `out`.
fn push_without_comments(line: &str, out: &mut String) {
    let mut depth = 0;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => break,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
}

/// The dialects other than `tried` that read `text` without an error, in `dialect::all()`'s
/// order: what a reader's refusal suggests.
pub fn readers_accepting(text: &str, tried: &dyn Dialect, machine: Option<Machine>) -> Vec<&'static str> {
    dialect::all()
        .into_iter()
        .filter(|d: &&dyn Dialect| d.name() != tried.name())
        .filter(|d| d.read(text, machine).is_ok())
        .map(|d| d.name())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_header_names_its_control_whatever_the_extension() {
        assert_eq!(guess("0 BEGIN PGM P MM\n1 END PGM P MM\n", Some("nc")).dialect.name(), "heidenhain");
        assert_eq!(guess("%_N_CAM_MPF\n;$PATH=/_N_MPF_DIR\nN10 G17\n", None).dialect.name(), "sinumerik");
    }

    #[test]
    fn words_tell_when_the_extension_does_not() {
        assert_eq!(guess("%\n(P)\nN10 G21 G18 G7 G90\n", Some("txt")).dialect.name(), "linuxcnc");
        assert_eq!(guess("N001 T1\nN003 X47.091 Z3 E\n", None).dialect.name(), "nc31");
        assert_eq!(guess("%\nO0001 (P)\nG0 X1.\n", None).dialect.name(), "iso");
        // G71 is Sinumerik's mm; G7 inside G71 is no G7.
        assert_eq!(guess("N10 G17 G90 G71\n", None).dialect.name(), "sinumerik");
        assert_eq!(guess("G0 X1 (G7 in a comment)\n", None).dialect.name(), "iso");
    }

    /// The words of one line are read in one pass, the first of [`TELLING`] winning whatever
    /// its place on the line; a leading zero and Sinumerik's `LIMS=` value are the same word.
    #[test]
    fn the_first_telling_word_of_a_line_wins_by_its_rank() {
        assert_eq!(guess("N10 G7 G71\n", None).reason, "the word G71");
        assert_eq!(guess("N10 g64 m02\n", None).reason, "the word M2");
        assert_eq!(guess("N10 LIMS=3000 G07\n", None).reason, "the word LIMS=");
        assert_eq!(guess("G0 X1 (DIAMON) E\n", None).reason, "the word E (the rapid mark)");
        assert_eq!(guess("E\n", None).dialect.name(), "nc31");
        assert_eq!(guess("G0 X1 ; G7\nN2 G1 X5.\n", None).reason, "the word X5. (a number ending in its point)");
    }

    /// A Fanuc program numbered in ISO code, `:1234` (the colon is the address O: FANUC 16i
    /// B-63524EN/01 §8 reads `:` as O), is iso, even when a later block holds a word that would
    /// tell another control (M2 is LinuxCNC's end, and Fanuc's too); a Sinumerik main block
    /// `:10` with its words tells nothing.
    #[test]
    fn a_colon_program_number_alone_in_its_block_is_a_fanuc_program() {
        let fanuc = guess("%\n:1234 (PART A)\nG0 X0 Y0\nG1 X10 F100\nM2\n%\n", None);
        assert_eq!(
            (fanuc.dialect.name(), fanuc.reason.as_str()),
            ("iso", "the word :1234 (a program number in ISO code)")
        );
        assert_eq!(guess(":0012 ;\nG0 X0 Y0\nM2\n", None).dialect.name(), "iso");
        assert_eq!(guess(":10 G0 X0\nM2\n", None).dialect.name(), "linuxcnc");
    }

    #[test]
    fn the_extension_comes_before_words() {
        assert_eq!(guess("G0 X1.\n", Some("NGC")).dialect.name(), "linuxcnc");
        assert_eq!(guess("G0 X1\n", Some("mpf")).dialect.name(), "sinumerik");
        assert_eq!(guess("G0 X1\n", Some("h")).dialect.name(), "heidenhain");
    }
}
