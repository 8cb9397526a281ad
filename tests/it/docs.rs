//! The README and the book cannot go stale: every `console` block in them is run and what it
//! shows is compared with what the program prints now, and every figure in `docs/` is
//! regenerated and compared byte for byte.
//!
//! # What a page may show, and how it is checked
//!
//! - A ```` ```console ```` block holds commands, each on a line starting `$ mtwin ` (or
//!   `$ cargo run --release -- `), each followed by the lines it prints. The commands of one page
//!   run in order, in one scratch folder that sees the checkout's `models/`, `scenarios/` and
//!   `tests/`, so a later block may read what an earlier one wrote (`out/…`). The lines shown
//!   must be the lines printed (standard output, then standard error), consecutively and in
//!   order; a line `…` (indented or not) stands for any number of lines, so `…` first shows the end of the output
//!   and `…` last its beginning. Trailing spaces do not count; nothing else is forgiven: every
//!   figure shown is the figure printed.
//! - A line `<!-- figure: docs/NAME from out/PATH -->` names a file the page's commands write
//!   as the figure `docs/NAME`: after the page's blocks have run, the two must be the same bytes.
//! - Every image under `docs/` is such a figure, or is named by a line
//!   `<!-- screenshot: docs/NAME -->`: a picture of an interactive viewer, which no command can
//!   redraw (its caption says so).
//!
//! `MTWIN_BLESS=1 cargo test --test it docs::` writes the figures anew (the one command that
//! regenerates every picture in `docs/`); the shown output is never rewritten, a stale page is
//! corrected by hand.

use std::path::{Path, PathBuf};

use crate::common::root;

/// One command of a `console` block and the lines shown under it.
#[derive(Debug)]
struct Shown {
    /// Page and line, for messages.
    place: String,
    /// The arguments after `mtwin`.
    args: Vec<String>,
    /// The lines shown, `…` included.
    lines: Vec<String>,
}

/// A page: its commands in order and the figures they write.
#[derive(Debug, Default)]
struct Page {
    commands: Vec<Shown>,
    /// (`docs/NAME`, `out/PATH`, line) of each `figure:` comment.
    figures: Vec<(String, String, usize)>,
    screenshots: Vec<String>,
}

const PREFIXES: [&str; 2] = ["$ mtwin ", "$ cargo run --release -- "];

/// The pages checked: the README and every chapter of the book.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    let book = root().join("docs/book/src");
    let mut chapters: Vec<PathBuf> = std::fs::read_dir(&book)
        .unwrap_or_else(|e| panic!("{}: {e}", book.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    chapters.sort();
    pages.extend(chapters);
    pages
}

fn parse(path: &Path) -> Page {
    let text = std::fs::read_to_string(path).unwrap();
    let name = path.strip_prefix(root()).unwrap().display().to_string();
    let mut page = Page::default();
    let mut in_console = false;
    let mut in_other = false;
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let place = format!("{name}:{number}");
        if in_console {
            if line.starts_with("```") {
                in_console = false;
            } else if let Some(rest) = PREFIXES.iter().find_map(|p| line.strip_prefix(p)) {
                page.commands.push(Shown {
                    place,
                    args: rest.split_whitespace().map(str::to_owned).collect(),
                    lines: Vec::new(),
                });
            } else {
                let shown = page.commands.last_mut().unwrap_or_else(|| {
                    panic!("{place}: a console block starts with `$ mtwin …`, not {line:?}")
                });
                shown.lines.push(line.trim_end().to_owned());
            }
        } else if in_other {
            in_other = !line.starts_with("```");
        } else if line.starts_with("```console") {
            in_console = true;
        } else if line.starts_with("```") {
            in_other = true;
        } else if let Some(rest) = comment(line, "figure:") {
            let (figure, from) = rest
                .split_once(" from ")
                .unwrap_or_else(|| panic!("{place}: `figure: docs/NAME from out/PATH`"));
            page.figures
                .push((figure.trim().to_owned(), from.trim().to_owned(), number));
        } else if let Some(rest) = comment(line, "screenshot:") {
            page.screenshots.push(rest.trim().to_owned());
        }
    }
    assert!(!in_console, "{name}: a console block is not closed");
    page
}

/// The body of `<!-- KEY … -->` on its own line.
fn comment<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.trim()
        .strip_prefix("<!--")?
        .strip_suffix("-->")?
        .trim()
        .strip_prefix(key)
}

/// Whether `shown` (segments separated by `…`) is `printed`, consecutively and in order: a
/// segment with no `…` before it starts at the first line printed, one with no `…` after it ends
/// at the last.
fn matches(shown: &[String], printed: &[String]) -> Result<(), String> {
    let segments: Vec<&[String]> = shown.split(|line| line.trim() == "…").collect();
    let mut at = 0;
    for (k, segment) in segments.iter().enumerate() {
        if segment.is_empty() {
            continue; // the `…` at either end
        }
        let (from_start, to_end) = (k == 0, k + 1 == segments.len());
        let fits = |s: usize| s >= at && printed.get(s..s + segment.len()) == Some(segment);
        let start = match (from_start, to_end) {
            (true, _) => fits(0).then_some(0),
            (false, true) => printed
                .len()
                .checked_sub(segment.len())
                .filter(|&s| fits(s)),
            (false, false) => (at..=printed.len()).find(|&s| fits(s)),
        };
        let Some(start) = start else {
            return Err(format!(
                "not printed where shown:\n  {}",
                segment.join("\n  ")
            ));
        };
        at = start + segment.len();
        if to_end && at != printed.len() {
            return Err(format!(
                "printed after the last line shown (end the block with `…` if that is meant):\n  {}",
                printed[at..].join("\n  ")
            ));
        }
    }
    Ok(())
}

/// A scratch folder that sees the checkout's inputs.
fn scratch() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["models", "scenarios", "tests"] {
        std::os::unix::fs::symlink(root().join(name), dir.path().join(name)).unwrap();
    }
    dir
}

fn run(dir: &Path, shown: &Shown) -> Vec<String> {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_mtwin"))
        .current_dir(dir)
        .args(&shown.args)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}: `mtwin {}` failed:\n{}",
        shown.place,
        shown.args.join(" "),
        String::from_utf8_lossy(&output.stderr)
    );
    let mut printed: Vec<String> = Vec::new();
    for stream in [&output.stdout, &output.stderr] {
        let text = std::str::from_utf8(stream).unwrap();
        printed.extend(text.lines().map(|l| l.trim_end().to_owned()));
    }
    printed
}

#[test]
fn every_console_block_prints_what_it_shows_and_every_figure_is_current() {
    let bless = std::env::var_os("MTWIN_BLESS").is_some();
    let mut stale = Vec::new();
    let mut figures = Vec::new();
    let mut screenshots = Vec::new();
    for path in pages() {
        let page = parse(&path);
        screenshots.extend(page.screenshots.iter().cloned());
        if page.commands.is_empty() && page.figures.is_empty() {
            continue;
        }
        let name = path.strip_prefix(root()).unwrap().display().to_string();
        let dir = scratch();
        for shown in &page.commands {
            let printed = run(dir.path(), shown);
            if shown.lines.is_empty() {
                continue; // a step whose output the page does not show
            }
            if let Err(why) = matches(&shown.lines, &printed) {
                stale.push(format!(
                    "{}: `mtwin {}`: {why}",
                    shown.place,
                    shown.args.join(" ")
                ));
            }
        }
        for (figure, from, line) in &page.figures {
            let made = std::fs::read(dir.path().join(from)).unwrap_or_else(|e| {
                panic!("{name}:{line}: the page's commands did not write {from}: {e}")
            });
            let kept = root().join(figure);
            if bless {
                std::fs::write(&kept, &made).unwrap();
            } else if std::fs::read(&kept).ok().as_deref() != Some(&made[..]) {
                stale.push(format!(
                    "{name}:{line}: {figure} is not what the program draws now ({from}); \
                     `MTWIN_BLESS=1 cargo test --test it docs::` draws it anew"
                ));
            }
            figures.push(figure.clone());
        }
    }
    // Every picture in docs/ is checked or declared a screenshot.
    for entry in std::fs::read_dir(root().join("docs")).unwrap() {
        let path = entry.unwrap().path();
        let is_picture = path
            .extension()
            .is_some_and(|e| ["png", "svg", "jpg", "jpeg", "gif"].contains(&e.to_str().unwrap()));
        if is_picture {
            let name = format!("docs/{}", path.file_name().unwrap().to_str().unwrap());
            assert!(
                figures.contains(&name) || screenshots.contains(&name),
                "{name} is neither a figure a page's commands draw nor a declared screenshot"
            );
        }
    }
    assert!(
        stale.is_empty(),
        "stale documentation:\n{}",
        stale.join("\n\n")
    );
}

fn lines(text: &str) -> Vec<String> {
    text.lines().map(str::to_owned).collect()
}

#[test]
fn shown_lines_match_only_what_is_printed_in_order() {
    let printed = lines("a\nb\nc\nd");
    assert!(matches(&lines("a\nb\nc\nd"), &printed).is_ok());
    assert!(matches(&lines("…\nc\nd"), &printed).is_ok());
    assert!(matches(&lines("a\n…"), &printed).is_ok());
    assert!(matches(&lines("a\n…\nd"), &printed).is_ok());
    assert!(matches(&lines("…\nb\n…"), &printed).is_ok());
    // A figure that changed, a line left out without `…`, lines in another order, a tail not
    // shown: each is stale.
    assert!(matches(&lines("a\nb\nc\ne"), &printed).is_err());
    assert!(matches(&lines("a\nc\nd"), &printed).is_err());
    assert!(matches(&lines("…\nd\nc"), &printed).is_err());
    assert!(matches(&lines("a\nb"), &printed).is_err());
    assert!(matches(&lines("…\nc"), &printed).is_err());
    assert!(matches(&lines("b\n…"), &printed).is_err());
}
