//! What an import tells the user it left out, bounded: a file's own text quoted in a note is
//! shortened, many notes of one kind (a defined name left out) are told as a count and the
//! first few, and the notes of one file are at most [`MAX_NOTES`]. A hostile file could
//! otherwise make a note line of megabytes (a 5 MB formula quoted whole) or a million lines
//! (300,000 defined names each refused).

use std::borrow::Cow;

/// The most characters of a file's text (a formula, a name's definition) one note quotes.
pub const MAX_QUOTED: usize = 200;

/// The most characters one note holds; past it the middle is left out, so that the note's
/// start (what and where) and its end (what ncsheet did about it) both stay.
pub const MAX_NOTE_CHARS: usize = 1_000;

/// The most notes one file's import gives; the rest are counted in a last note.
pub const MAX_NOTES: usize = 50;

/// How many notes of one kind are told one by one before the rest are counted.
pub const LISTED: usize = 5;

/// `text` as a note quotes it: whole when short, else its first [`MAX_QUOTED`] characters and
/// how many there are.
pub fn quoted(text: &str) -> Cow<'_, str> {
    match text.char_indices().nth(MAX_QUOTED) {
        None => Cow::Borrowed(text),
        Some((cut, _)) => Cow::Owned(format!("{}… ({} characters in all)", &text[..cut], text.chars().count())),
    }
}

/// Notes of one kind (each defined name a reader left out): the first [`LISTED`] as they are,
/// the rest as a count in one note.
#[derive(Default)]
pub struct Grouped {
    listed: Vec<String>,
    more: usize,
}

impl Grouped {
    pub fn push(&mut self, note: String) {
        if self.listed.len() < LISTED {
            self.listed.push(note);
        } else {
            self.more += 1;
        }
    }

    /// The notes into `notes`, the ones past the first few as `and N more <what>`.
    pub fn finish(self, what: &str, notes: &mut Vec<String>) {
        notes.extend(self.listed);
        if self.more > 0 {
            notes.push(format!("and {} more {what} (their notes are not shown)", self.more));
        }
    }
}

/// Lines of several kinds, too many to print (the problems of 200,000 cells were 400,000
/// lines): the first [`MAX_NOTES`] are told, the rest counted by kind, each kind in one last
/// line, in the order the kinds first came.
#[derive(Default)]
pub struct Capped {
    told: usize,
    more: Vec<(&'static str, usize)>,
}

impl Capped {
    /// Whether the next line, of kind `what` (a plural: `formulas that do not parse`), is
    /// told; a line not told is counted under its kind.
    pub fn tell(&mut self, what: &'static str) -> bool {
        if self.told < MAX_NOTES {
            self.told += 1;
            return true;
        }
        match self.more.iter_mut().find(|(kind, _)| *kind == what) {
            Some((_, n)) => *n += 1,
            None => self.more.push((what, 1)),
        }
        false
    }

    /// The lines counting what was not told, each saying `why`: `and 199950 more formulas
    /// that do not parse (why)`.
    pub fn finish(self, why: &str) -> Vec<String> {
        self.more.into_iter().map(|(what, n)| format!("and {n} more {what} ({why})")).collect()
    }
}

/// One file's notes as the user hears them: each at most [`MAX_NOTE_CHARS`] characters, at
/// most [`MAX_NOTES`] of them, the last saying how many were not shown.
pub fn bounded(mut notes: Vec<String>) -> Vec<String> {
    if notes.len() > MAX_NOTES {
        let hidden = notes.len() - (MAX_NOTES - 1);
        notes.truncate(MAX_NOTES - 1);
        notes.push(format!("and {hidden} more notes on what the file holds that were not shown"));
    }
    for note in &mut notes {
        if let Some(short) = shortened(note) {
            *note = short;
        }
    }
    notes
}

/// A note past [`MAX_NOTE_CHARS`] with its middle left out, `None` when it is short enough.
fn shortened(note: &str) -> Option<String> {
    let total = note.chars().count();
    if total <= MAX_NOTE_CHARS {
        return None;
    }
    let head = MAX_NOTE_CHARS * 2 / 3;
    let tail = MAX_NOTE_CHARS - head;
    let head_end = note.char_indices().nth(head).map_or(note.len(), |(i, _)| i);
    let tail_start = note.char_indices().nth(total - tail).map_or(note.len(), |(i, _)| i);
    Some(format!("{} … ({} characters not shown) … {}", &note[..head_end], total - head - tail, &note[tail_start..]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_quote_is_cut_at_a_character_and_counted() {
        let text = "é".repeat(MAX_QUOTED + 10);
        let q = quoted(&text);
        assert!(q.starts_with(&"é".repeat(MAX_QUOTED)));
        assert!(q.ends_with(&format!("({} characters in all)", MAX_QUOTED + 10)));
        assert_eq!(quoted("=A1"), "=A1");
    }

    #[test]
    fn many_notes_end_in_a_count_and_a_long_one_keeps_both_ends() {
        let notes: Vec<String> = (0..MAX_NOTES + 7).map(|i| format!("note {i}")).collect();
        let out = bounded(notes);
        assert_eq!(out.len(), MAX_NOTES);
        assert_eq!(out[MAX_NOTES - 1], "and 8 more notes on what the file holds that were not shown");
        let long = format!("start {} end", "x".repeat(5_000));
        let out = bounded(vec![long]);
        assert!(out[0].starts_with("start ") && out[0].ends_with(" end"));
        assert!(out[0].chars().count() < MAX_NOTE_CHARS + 60);
    }

    #[test]
    fn capped_lines_past_the_first_fifty_are_counted_by_kind() {
        let mut capped = Capped::default();
        let kinds = ["a", "b"];
        let told = (0..MAX_NOTES + 5).filter(|i| capped.tell(kinds[usize::from(*i >= MAX_NOTES + 2)])).count();
        assert_eq!(told, MAX_NOTES);
        assert_eq!(capped.finish("not shown"), ["and 2 more a (not shown)", "and 3 more b (not shown)"]);
    }

    #[test]
    fn a_group_tells_the_first_few_and_counts_the_rest() {
        let mut group = Grouped::default();
        for i in 0..8 {
            group.push(format!("name n{i} was left out"));
        }
        let mut notes = Vec::new();
        group.finish("defined names were left out", &mut notes);
        assert_eq!(notes.len(), LISTED + 1);
        assert_eq!(notes[LISTED], "and 3 more defined names were left out (their notes are not shown)");
    }
}
