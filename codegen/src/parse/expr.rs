//! Numbers in the grammar: constant expressions (`-9.81`, `pi / 2.0`, `(0.3 + 0.1) * 2.0`),
//! names (a parameter, `pi`, `world`, `none`), lists and calls (`[x, y, z]`, `diag(a, b, c)`),
//! labelled list elements (`[left_sole: six_d]`), parsed with the usual precedence and printed
//! back as written.

use std::fmt;

use proc_macro2::{Ident, TokenStream};
use quote::ToTokens;
use syn::ext::IdentExt;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{bracketed, parenthesized, token, Lit, Token};

/// A value: a number expression, a name, a list or a call such as `diag(…)`. What a value may
/// be depends on where it stands; `lower` checks it.
#[derive(Clone, Debug)]
pub enum Expr {
    /// An integer or float literal.
    Number(Lit),
    /// A name: `pi`, a parameter, a body, `world`, `none`, an output, `x`, `xyz`, ….
    Name(Ident),
    /// `-e`.
    Neg(Token![-], Box<Expr>),
    /// `a + b`, `a - b`, `a * b`, `a / b`.
    Binary(Box<Expr>, BinOp, Box<Expr>),
    /// `(e)`.
    Paren(token::Paren, Box<Expr>),
    /// `[a, b, …]`.
    List(token::Bracket, Punctuated<Expr, Token![,]>),
    /// `name(a, b, …)`.
    Call(Ident, token::Paren, Punctuated<Expr, Token![,]>),
    /// `label: value`, an element of a list only: `[left_sole: six_d]`, `[rod: point(a, b)]`.
    Labeled(Ident, Token![:], Box<Expr>),
}

/// A binary operator in a number expression.
#[derive(Clone, Copy, Debug)]
pub enum BinOp {
    /// `+`
    Add(Token![+]),
    /// `-`
    Sub(Token![-]),
    /// `*`
    Mul(Token![*]),
    /// `/`
    Div(Token![/]),
}

impl BinOp {
    fn precedence(self) -> u8 {
        match self {
            BinOp::Add(_) | BinOp::Sub(_) => 1,
            BinOp::Mul(_) | BinOp::Div(_) => 2,
        }
    }
    fn symbol(self) -> &'static str {
        match self {
            BinOp::Add(_) => "+",
            BinOp::Sub(_) => "-",
            BinOp::Mul(_) => "*",
            BinOp::Div(_) => "/",
        }
    }
    fn peek(input: ParseStream) -> syn::Result<Option<BinOp>> {
        Ok(if input.peek(Token![+]) && !input.peek(Token![+=]) {
            Some(BinOp::Add(input.parse()?))
        } else if input.peek(Token![-]) && !input.peek(Token![-=]) && !input.peek(Token![->]) {
            Some(BinOp::Sub(input.parse()?))
        } else if input.peek(Token![*]) && !input.peek(Token![*=]) {
            Some(BinOp::Mul(input.parse()?))
        } else if input.peek(Token![/]) && !input.peek(Token![/=]) {
            Some(BinOp::Div(input.parse()?))
        } else {
            None
        })
    }
    fn peek_precedence(input: ParseStream) -> Option<u8> {
        let fork = input.fork();
        BinOp::peek(&fork).ok().flatten().map(BinOp::precedence)
    }
}

impl Parse for Expr {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        parse_binary(input, 0)
    }
}

/// Precedence climbing: parses operands joined by operators binding tighter than `min`.
fn parse_binary(input: ParseStream, min: u8) -> syn::Result<Expr> {
    let mut lhs = parse_unary(input)?;
    while let Some(prec) = BinOp::peek_precedence(input) {
        if prec <= min {
            break;
        }
        let Some(op) = BinOp::peek(input)? else {
            break;
        };
        let rhs = parse_binary(input, prec)?;
        lhs = Expr::Binary(Box::new(lhs), op, Box::new(rhs));
    }
    Ok(lhs)
}

fn parse_unary(input: ParseStream) -> syn::Result<Expr> {
    if input.peek(Token![-]) {
        let minus = input.parse()?;
        Ok(Expr::Neg(minus, Box::new(parse_unary(input)?)))
    } else {
        parse_primary(input)
    }
}

fn parse_primary(input: ParseStream) -> syn::Result<Expr> {
    let lookahead = input.lookahead1();
    if lookahead.peek(syn::LitFloat) || lookahead.peek(syn::LitInt) {
        Ok(Expr::Number(input.parse()?))
    } else if lookahead.peek(Ident::peek_any) {
        let name = input.call(Ident::parse_any)?;
        if input.peek(token::Paren) {
            let content;
            let paren = parenthesized!(content in input);
            let args = content.parse_terminated(Expr::parse, Token![,])?;
            Ok(Expr::Call(name, paren, args))
        } else {
            Ok(Expr::Name(name))
        }
    } else if lookahead.peek(token::Paren) {
        let content;
        let paren = parenthesized!(content in input);
        let inner: Expr = content.parse()?;
        if !content.is_empty() {
            return Err(content.error("expected `)`"));
        }
        Ok(Expr::Paren(paren, Box::new(inner)))
    } else if lookahead.peek(token::Bracket) {
        let content;
        let bracket = bracketed!(content in input);
        let elems = content.parse_terminated(parse_element, Token![,])?;
        Ok(Expr::List(bracket, elems))
    } else {
        Err(lookahead.error())
    }
}

/// An element of a list: a value, or `label: value`.
fn parse_element(input: ParseStream) -> syn::Result<Expr> {
    if input.peek(Ident::peek_any) && input.peek2(Token![:]) && !input.peek2(Token![::]) {
        let label = input.call(Ident::parse_any)?;
        let colon = input.parse()?;
        Ok(Expr::Labeled(label, colon, Box::new(input.parse()?)))
    } else {
        input.parse()
    }
}

impl ToTokens for Expr {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        match self {
            Expr::Number(lit) => lit.to_tokens(tokens),
            Expr::Name(name) => name.to_tokens(tokens),
            Expr::Neg(minus, e) => {
                minus.to_tokens(tokens);
                e.to_tokens(tokens);
            }
            Expr::Binary(l, op, r) => {
                l.to_tokens(tokens);
                op.to_tokens(tokens);
                r.to_tokens(tokens);
            }
            Expr::Paren(paren, e) => paren.surround(tokens, |t| e.to_tokens(t)),
            Expr::List(bracket, elems) => bracket.surround(tokens, |t| elems.to_tokens(t)),
            Expr::Call(name, paren, args) => {
                name.to_tokens(tokens);
                paren.surround(tokens, |t| args.to_tokens(t));
            }
            Expr::Labeled(label, colon, e) => {
                label.to_tokens(tokens);
                colon.to_tokens(tokens);
                e.to_tokens(tokens);
            }
        }
    }
}

impl ToTokens for BinOp {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        match self {
            BinOp::Add(t) => t.to_tokens(tokens),
            BinOp::Sub(t) => t.to_tokens(tokens),
            BinOp::Mul(t) => t.to_tokens(tokens),
            BinOp::Div(t) => t.to_tokens(tokens),
        }
    }
}

/// Writes the expression back as the user would: `[0.0, pi / 2.0, 0.0]`, `diag(1, 2, 3)`.
/// Messages quote values this way.
impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fn list(f: &mut fmt::Formatter<'_>, elems: &Punctuated<Expr, Token![,]>) -> fmt::Result {
            for (i, e) in elems.iter().enumerate() {
                if i > 0 {
                    f.write_str(", ")?;
                }
                write!(f, "{e}")?;
            }
            Ok(())
        }
        match self {
            Expr::Number(lit) => write!(f, "{}", lit.to_token_stream()),
            Expr::Name(name) => write!(f, "{name}"),
            Expr::Neg(_, e) => write!(f, "-{e}"),
            Expr::Binary(l, op, r) => write!(f, "{l} {} {r}", op.symbol()),
            Expr::Paren(_, e) => write!(f, "({e})"),
            Expr::List(_, elems) => {
                f.write_str("[")?;
                list(f, elems)?;
                f.write_str("]")
            }
            Expr::Call(name, _, args) => {
                write!(f, "{name}(")?;
                list(f, args)?;
                f.write_str(")")
            }
            Expr::Labeled(label, _, e) => write!(f, "{label}: {e}"),
        }
    }
}
