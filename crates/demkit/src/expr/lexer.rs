//! The lexer: source text to tokens with their 1-based columns.

use super::{ExprError, ExprErrorKind};

#[derive(Debug, Clone, PartialEq)]
pub(super) enum TokKind {
    Num(f64),
    Ident(String),
    /// Operators and punctuation: `+ - * / ^ ( ) ,` and the comparisons; `**` becomes `^`.
    Sym(&'static str),
}

impl TokKind {
    pub(super) fn describe(&self) -> String {
        match self {
            TokKind::Num(v) => format!("number {v}"),
            TokKind::Ident(s) => format!("name '{s}'"),
            TokKind::Sym(s) => format!("'{s}'"),
        }
    }
}

#[derive(Debug, Clone)]
pub(super) struct Token {
    pub(super) kind: TokKind,
    pub(super) column: usize,
}

/// Splits `source` into tokens; an unknown character or a malformed number is an error.
pub(super) fn lex(source: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = source.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && chars[i].is_ascii_digit() {
                i += 1;
            }
            if i < chars.len() && chars[i] == '.' {
                i += 1;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            // An exponent only if digits follow (`2e` is the number 2 then the name `e`).
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let text: String = chars[start..i].iter().collect();
            let value = text.parse::<f64>().map_err(|_| ExprError {
                kind: ExprErrorKind::Syntax(format!("bad number '{text}'")),
                column,
            })?;
            tokens.push(Token {
                kind: TokKind::Num(value),
                column,
            });
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push(Token {
                kind: TokKind::Ident(chars[start..i].iter().collect()),
                column,
            });
            continue;
        }
        let next = chars.get(i + 1).copied();
        let (sym, len): (&'static str, usize) = match (c, next) {
            ('<', Some('=')) => ("<=", 2),
            ('>', Some('=')) => (">=", 2),
            ('=', Some('=')) => ("==", 2),
            ('!', Some('=')) => ("!=", 2),
            ('*', Some('*')) => ("^", 2),
            ('<', _) => ("<", 1),
            ('>', _) => (">", 1),
            ('+', _) => ("+", 1),
            ('-', _) => ("-", 1),
            ('*', _) => ("*", 1),
            ('/', _) => ("/", 1),
            ('^', _) => ("^", 1),
            ('(', _) => ("(", 1),
            (')', _) => (")", 1),
            (',', _) => (",", 1),
            ('=', _) => {
                return Err(ExprError {
                    kind: ExprErrorKind::Syntax("'=' is not an operator (use '==')".into()),
                    column,
                });
            }
            _ => {
                return Err(ExprError {
                    kind: ExprErrorKind::Syntax(format!("unexpected character '{c}'")),
                    column,
                });
            }
        };
        tokens.push(Token {
            kind: TokKind::Sym(sym),
            column,
        });
        i += len;
    }
    Ok(tokens)
}
