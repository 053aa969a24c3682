//! Editing one line of text (the texture path prompt): a cursor, moves by
//! character and to either end, deletion before and under the cursor, of
//! the line before it (Ctrl-U) and of the word before it (Ctrl-W), and
//! completion of file paths (Tab).

/// An edit of the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edit {
    Left,
    Right,
    Home,
    End,
    /// Backspace: the character before the cursor.
    Backspace,
    /// Delete: the character under the cursor.
    Delete,
    /// Ctrl-U: everything before the cursor.
    KillToStart,
    /// Ctrl-W: the word before the cursor (and the blanks after it), as
    /// a shell's line editor does; a `/` also ends a word here, so a path
    /// loses one component at a time.
    KillWord,
}

/// `cursor` moved onto a character boundary of `text`, within it.
pub fn clamp(text: &str, cursor: usize) -> usize {
    let mut c = cursor.min(text.len());
    while !text.is_char_boundary(c) {
        c -= 1;
    }
    c
}

fn prev(text: &str, cursor: usize) -> usize {
    text[..cursor]
        .char_indices()
        .next_back()
        .map_or(0, |(i, _)| i)
}

fn next(text: &str, cursor: usize) -> usize {
    text[cursor..]
        .chars()
        .next()
        .map_or(cursor, |c| cursor + c.len_utf8())
}

/// Applies `edit` to `text` with the cursor at byte `cursor`; returns the
/// new cursor.
pub fn apply(text: &mut String, cursor: usize, edit: Edit) -> usize {
    let c = clamp(text, cursor);
    match edit {
        Edit::Left => prev(text, c),
        Edit::Right => next(text, c),
        Edit::Home => 0,
        Edit::End => text.len(),
        Edit::Backspace => {
            let p = prev(text, c);
            text.replace_range(p..c, "");
            p
        }
        Edit::Delete => {
            let n = next(text, c);
            text.replace_range(c..n, "");
            c
        }
        Edit::KillToStart => {
            text.replace_range(..c, "");
            0
        }
        Edit::KillWord => {
            let before = &text[..c];
            let trimmed = before.trim_end_matches([' ', '/']);
            let start = trimmed.rfind([' ', '/']).map_or(0, |i| i + 1);
            text.replace_range(start..c, "");
            start
        }
    }
}

/// Inserts `s` at the cursor; returns the new cursor.
pub fn insert(text: &mut String, cursor: usize, s: &str) -> usize {
    let c = clamp(text, cursor);
    text.insert_str(c, s);
    c + s.len()
}

/// What Tab found for the path before the cursor.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Completion {
    /// The text before the cursor, completed as far as every match agrees
    /// (a lone folder gets its `/`).
    pub completed: String,
    /// The names that match, when more than one does (sorted, at most a
    /// few for the message).
    pub choices: Vec<String>,
    /// How many names match.
    pub matches: usize,
}

/// Most choices a completion lists.
const MAX_CHOICES: usize = 8;

/// Completes the path `typed` from the files in its folder (the current
/// folder when it names none). Hidden files match only a name that starts
/// with a dot. Reads the folder: the loop calls it, not `update`.
pub fn complete_path(typed: &str) -> Completion {
    let (dir, partial) = match typed.rfind('/') {
        Some(i) => (&typed[..=i], &typed[i + 1..]),
        None => ("", typed),
    };
    let folder = if dir.is_empty() { "." } else { dir };
    let mut names: Vec<(String, bool)> = std::fs::read_dir(folder)
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            let hidden = name.starts_with('.') && !partial.starts_with('.');
            if hidden || !name.starts_with(partial) {
                return None;
            }
            // A link to a folder is a folder here.
            let is_dir = std::fs::metadata(e.path()).is_ok_and(|m| m.is_dir());
            Some((name, is_dir))
        })
        .collect();
    names.sort();
    let matches = names.len();
    let completed = match names.as_slice() {
        [] => typed.to_string(),
        [(name, is_dir)] => format!("{dir}{name}{}", if *is_dir { "/" } else { "" }),
        [(first, _), rest @ ..] => {
            let mut common = first.as_str();
            for (name, _) in rest {
                let n = common
                    .char_indices()
                    .zip(name.chars())
                    .find(|((_, a), b)| a != b)
                    .map_or(common.len().min(name.len()), |((i, _), _)| i);
                common = &common[..n];
            }
            format!("{dir}{common}")
        }
    };
    let choices = if matches > 1 {
        names
            .into_iter()
            .take(MAX_CHOICES)
            .map(|(n, d)| if d { format!("{n}/") } else { n })
            .collect()
    } else {
        Vec::new()
    };
    Completion {
        completed,
        choices,
        matches,
    }
}
