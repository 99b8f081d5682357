//! The text of a `.chain` file: tokenized with line and column spans, parsed, lowered; errors as
//! `path:line:column: error: message`.

extern crate proc_macro;

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use proc_macro2::TokenStream;

use crate::lower::lower;
use crate::options::Description;
use crate::parse::ChainDef;

/// Everything wrong with one description file, each problem at its line and column.
#[derive(Debug)]
pub struct FileError {
    /// The file, as given by the caller.
    pub path: PathBuf,
    /// The problems, in source order.
    pub diagnostics: Vec<Diagnostic>,
}

/// One problem in a description file.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// 1-based line of the offending token.
    pub line: usize,
    /// 1-based column (in characters) of the offending token.
    pub column: usize,
    /// What is wrong: expected vs found, quoting the user's names.
    pub message: String,
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: error: {}", self.line, self.column, self.message)
    }
}

/// One line per diagnostic: `path:line:column: error: message`.
impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.display();
        for (i, d) in self.diagnostics.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{path}:{d}")?;
        }
        Ok(())
    }
}

impl std::error::Error for FileError {}

/// Parses and lowers the text of a `.chain` file. `path` is used only in messages.
///
/// Spans carry line and column through proc-macro2's `span-locations` feature, so every
/// diagnostic names the offending token's line and column.
///
/// # Errors
/// Every problem found, each with its line and column.
pub fn parse_chain_str(src: &str, path: &Path) -> Result<Description, FileError> {
    let _lexer = FallbackLexer::new();
    let fail = |diagnostics: Vec<Diagnostic>| FileError {
        path: path.to_path_buf(),
        diagnostics,
    };
    let tokens = TokenStream::from_str(src).map_err(|e| fail(vec![lex_diagnostic(&e, src)]))?;
    let def: ChainDef = syn::parse2(tokens).map_err(|e| fail(diagnostics(e, src)))?;
    lower(&def).map_err(|e| fail(diagnostics(e, src)))
}

/// Inside a proc macro (a macro that reads a `.chain` file), the compiler would tokenize the text
/// with call-site spans, which know nothing of the file's lines. While this guard lives,
/// proc-macro2 uses its own lexer instead, whose spans carry the file's line and column. No token
/// escapes [`parse_chain_str`], so nothing mixes the two kinds of span. Outside a macro this does
/// nothing.
struct FallbackLexer {
    forced: bool,
}

impl FallbackLexer {
    fn new() -> Self {
        let forced = proc_macro::is_available();
        if forced {
            proc_macro2::fallback::force();
        }
        FallbackLexer { forced }
    }
}

impl Drop for FallbackLexer {
    fn drop(&mut self) {
        if self.forced {
            proc_macro2::fallback::unforce();
        }
    }
}

/// Splits a (combined) `syn::Error` into diagnostics sorted by position.
fn diagnostics(err: syn::Error, src: &str) -> Vec<Diagnostic> {
    let mut out: Vec<Diagnostic> = err
        .into_iter()
        .map(|e| {
            let start = e.span().start();
            let message = e.to_string();
            let (line, column) = if start.line == 0
                || (message.contains("end of input") && start.line == 1 && start.column == 0)
            {
                // syn reports the end of the top-level input at the call site, which outside a
                // macro has no place in the file: point after the last token instead.
                end_of_file(src)
            } else {
                (start.line, start.column + 1)
            };
            Diagnostic {
                line,
                column,
                message,
            }
        })
        .collect();
    out.sort_by_key(|d| (d.line, d.column));
    out
}

/// Line and column just after the last non-whitespace character.
fn end_of_file(src: &str) -> (usize, usize) {
    let trimmed = src.trim_end();
    let line = trimmed.lines().count().max(1);
    let column = trimmed.lines().last().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// A tokenizer error, explained from the character it stops at.
fn lex_diagnostic(err: &proc_macro2::LexError, src: &str) -> Diagnostic {
    let start = err.span().start();
    let (line, column) = (start.line.max(1), start.column + 1);
    let at = src
        .lines()
        .nth(line - 1)
        .and_then(|l| l.chars().nth(column - 1));
    let message = match at {
        Some(open @ ('(' | '[' | '{')) => {
            let close = match open {
                '(' => ')',
                '[' => ']',
                _ => '}',
            };
            format!("unclosed delimiter `{open}`: expected a matching `{close}` before the end of the file")
        }
        Some(close @ (')' | ']' | '}')) => format!(
            "unexpected closing delimiter `{close}`: it does not match the innermost open delimiter"
        ),
        Some('"') => "unterminated string literal: expected a closing `\"`".to_string(),
        Some(c) => {
            format!("cannot read a token at `{c}`: expected a name, a number or punctuation")
        }
        None => "cannot tokenize the file: unexpected end of input".to_string(),
    };
    Diagnostic {
        line,
        column,
        message,
    }
}
