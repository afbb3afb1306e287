//! The expression language of matrix entries and entry equations.
//!
//! Grammar (whitespace is free):
//!
//! ```text
//! expr    := term (('+' | '-') term)*
//! term    := unary (('*' | '/') unary)*
//! unary   := '-' unary | atom
//! atom    := NUMBER | NAME | NAME '[' INT ']' '[' INT ']' | 'sqrt' '(' expr ')' | '(' expr ')'
//! ```
//!
//! `NUMBER` is a decimal literal (read exactly: `0.5625` is `9/16`), `NAME` a
//! parameter, and `NAME[i][j]` the entry at row `i`, column `j` (from 0) of
//! the matrix of arrow `NAME`.

use std::fmt;

use std::str::FromStr;

use super::num::{MAX_EXPONENT, Num};
use super::surd::{Surd, SurdError};

/// A parsed expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A literal number.
    Num(Num),
    /// A parameter, with its byte offset in the source text.
    Param(String, usize),
    /// An entry `arrow[row][col]`, with its byte offset in the source text.
    Entry {
        /// Arrow name.
        arrow: String,
        /// Row, from 0.
        row: usize,
        /// Column, from 0.
        col: usize,
        /// Byte offset in the source text.
        offset: usize,
    },
    /// `-e`.
    Neg(Box<Expr>),
    /// `a + b`.
    Add(Box<Expr>, Box<Expr>),
    /// `a - b`.
    Sub(Box<Expr>, Box<Expr>),
    /// `a * b`.
    Mul(Box<Expr>, Box<Expr>),
    /// `a / b`.
    Div(Box<Expr>, Box<Expr>),
    /// `sqrt(e)`.
    Sqrt(Box<Expr>),
}

/// A syntax error in an expression: byte offset and what was expected.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct ExprSyntaxError {
    /// Byte offset of the offending character in the expression text.
    pub offset: usize,
    /// What was found and what was expected.
    pub message: String,
}

/// What an expression may fail with when it is evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExprError {
    /// A name that is neither a parameter nor a known constant.
    #[error("unknown parameter `{0}`")]
    UnknownParam(String, usize),
    /// An entry of an arrow that does not exist or is out of range.
    #[error("no entry {arrow}[{row}][{col}]")]
    UnknownEntry {
        /// Arrow name.
        arrow: String,
        /// Row.
        row: usize,
        /// Column.
        col: usize,
        /// Byte offset in the source text.
        offset: usize,
    },
    /// Division by zero, or by an expression that depends on unknowns.
    #[error("division by zero or by an expression that depends on unknowns")]
    BadDivision,
    /// Square root of a negative number or of an expression that depends on unknowns.
    #[error("square root of a negative number or of an expression that depends on unknowns")]
    BadSqrt,
    /// A product of two expressions that both depend on unknowns.
    #[error("product of two expressions that both depend on unknowns is not linear")]
    Nonlinear,
}

/// Arithmetic an expression needs from the values it is evaluated to.
pub trait ExprValue: Sized {
    /// The value of a literal.
    fn from_num(n: &Num) -> Self;
    /// `self + other`.
    fn plus(&self, other: &Self) -> Self;
    /// `self - other`.
    fn minus(&self, other: &Self) -> Self;
    /// `self * other`, or an error when it would not be linear.
    fn times(&self, other: &Self) -> Result<Self, ExprError>;
    /// `self / other`.
    fn divide(&self, other: &Self) -> Result<Self, ExprError>;
    /// `sqrt(self)`.
    fn root(&self) -> Result<Self, ExprError>;
}

impl ExprValue for f64 {
    fn from_num(n: &Num) -> f64 {
        n.to_f64()
    }
    fn plus(&self, other: &f64) -> f64 {
        self + other
    }
    fn minus(&self, other: &f64) -> f64 {
        self - other
    }
    fn times(&self, other: &f64) -> Result<f64, ExprError> {
        Ok(self * other)
    }
    fn divide(&self, other: &f64) -> Result<f64, ExprError> {
        if *other == 0.0 { Err(ExprError::BadDivision) } else { Ok(self / other) }
    }
    fn root(&self) -> Result<f64, ExprError> {
        if *self < 0.0 { Err(ExprError::BadSqrt) } else { Ok(self.sqrt()) }
    }
}

impl ExprValue for Num {
    fn from_num(n: &Num) -> Num {
        n.clone()
    }
    fn plus(&self, other: &Num) -> Num {
        self.add(other)
    }
    fn minus(&self, other: &Num) -> Num {
        self.sub(other)
    }
    fn times(&self, other: &Num) -> Result<Num, ExprError> {
        Ok(self.mul(other))
    }
    fn divide(&self, other: &Num) -> Result<Num, ExprError> {
        self.div(other).ok_or(ExprError::BadDivision)
    }
    fn root(&self) -> Result<Num, ExprError> {
        self.sqrt().ok_or(ExprError::BadSqrt)
    }
}

impl FromStr for Num {
    type Err = SurdError;

    /// A constant expression (`0.25`, `1/4`, `sqrt(3)/6`, `-1e-3`): exact
    /// when it is a surd, approximate otherwise.
    fn from_str(text: &str) -> Result<Num, SurdError> {
        let e =
            Expr::parse(text).map_err(|e| SurdError::Syntax { text: text.to_string(), message: e.message.clone() })?;
        e.eval_constant().map_err(|e| match e {
            ExprError::BadDivision => SurdError::DivisionByZero(text.to_string()),
            ExprError::BadSqrt => SurdError::Inexact(text.to_string()),
            _ => SurdError::NotConstant(text.to_string()),
        })
    }
}

/// Constant texts as exact surds (the parser lives here, above the numbers).
impl Surd {
    /// Parses a constant expression (`1/2`, `-sqrt(3)/18`, `(1 + sqrt(5))/2`).
    ///
    /// # Errors
    /// A syntax error, a parameter, or an operation that leaves the surds.
    pub fn parse(text: &str) -> Result<Surd, SurdError> {
        let e =
            Expr::parse(text).map_err(|e| SurdError::Syntax { text: text.to_string(), message: e.message.clone() })?;
        Surd::from_expr(&e, text)
    }

    /// The exact value of a constant expression.
    ///
    /// # Errors
    /// See [`Surd::parse`]; `text` is quoted in the error.
    pub fn from_expr(e: &Expr, text: &str) -> Result<Surd, SurdError> {
        match e.eval_constant() {
            Ok(Num::Exact(s)) => Ok(s),
            Ok(Num::Approx(_)) | Err(ExprError::BadSqrt) => Err(SurdError::Inexact(text.to_string())),
            Err(ExprError::BadDivision) => Err(SurdError::DivisionByZero(text.to_string())),
            Err(_) => Err(SurdError::NotConstant(text.to_string())),
        }
    }
}

/// Where an expression finds the values of its names.
pub trait Env<V> {
    /// The value of parameter `name`, if there is one.
    fn param(&self, name: &str) -> Option<V>;
    /// The value of entry `arrow[row][col]`, if there is one.
    fn entry(&self, arrow: &str, row: usize, col: usize) -> Option<V>;
}

/// Constants only: any name is unknown.
struct NoNames;

impl<V> Env<V> for NoNames {
    fn param(&self, _: &str) -> Option<V> {
        None
    }
    fn entry(&self, _: &str, _: usize, _: usize) -> Option<V> {
        None
    }
}

impl Expr {
    /// Parses `text`.
    pub fn parse(text: &str) -> Result<Expr, ExprSyntaxError> {
        let mut p = Parser { text, pos: 0, depth: 0, operations: 0 };
        let e = p.expr()?;
        p.skip_ws();
        if p.pos < text.len() {
            return Err(p.error("an operator (+ - * /) or the end of the expression"));
        }
        Ok(e)
    }

    /// Evaluates the expression in `env`.
    pub fn eval<V: ExprValue>(&self, env: &dyn Env<V>) -> Result<V, ExprError> {
        Ok(match self {
            Expr::Num(n) => V::from_num(n),
            Expr::Param(name, offset) => {
                env.param(name).ok_or_else(|| ExprError::UnknownParam(name.clone(), *offset))?
            }
            Expr::Entry { arrow, row, col, offset } => env.entry(arrow, *row, *col).ok_or_else(|| {
                ExprError::UnknownEntry { arrow: arrow.clone(), row: *row, col: *col, offset: *offset }
            })?,
            Expr::Neg(e) => V::from_num(&Num::zero()).minus(&e.eval(env)?),
            Expr::Add(a, b) => a.eval(env)?.plus(&b.eval(env)?),
            Expr::Sub(a, b) => a.eval(env)?.minus(&b.eval(env)?),
            Expr::Mul(a, b) => a.eval(env)?.times(&b.eval(env)?)?,
            Expr::Div(a, b) => a.eval(env)?.divide(&b.eval(env)?)?,
            Expr::Sqrt(e) => e.eval(env)?.root()?,
        })
    }

    /// The value of an expression of constants only (numbers, `+ - * /`,
    /// `sqrt`): exact when it is a surd.
    ///
    /// # Errors
    /// A name or an entry (not a constant), a division by zero, the square
    /// root of a negative number.
    pub fn eval_constant(&self) -> Result<Num, ExprError> {
        self.eval(&NoNames)
    }

    /// Every entry reference `(arrow, row, col, offset)` in the expression.
    pub fn entries(&self) -> Vec<(&str, usize, usize, usize)> {
        let mut out = Vec::new();
        self.walk(&mut |e| {
            if let Expr::Entry { arrow, row, col, offset } = e {
                out.push((arrow.as_str(), *row, *col, *offset));
            }
        });
        out
    }

    /// Every parameter name `(name, offset)` in the expression.
    pub fn params(&self) -> Vec<(&str, usize)> {
        let mut out = Vec::new();
        self.walk(&mut |e| {
            if let Expr::Param(name, offset) = e {
                out.push((name.as_str(), *offset));
            }
        });
        out
    }

    fn walk<'a>(&'a self, f: &mut dyn FnMut(&'a Expr)) {
        f(self);
        match self {
            Expr::Neg(e) | Expr::Sqrt(e) => e.walk(f),
            Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) | Expr::Div(a, b) => {
                a.walk(f);
                b.walk(f);
            }
            _ => {}
        }
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Expr::Num(n) => write!(f, "{n}"),
            Expr::Param(name, _) => write!(f, "{name}"),
            Expr::Entry { arrow, row, col, .. } => write!(f, "{arrow}[{row}][{col}]"),
            Expr::Neg(e) => write!(f, "-({e})"),
            Expr::Add(a, b) => write!(f, "({a} + {b})"),
            Expr::Sub(a, b) => write!(f, "({a} - {b})"),
            Expr::Mul(a, b) => write!(f, "{a}*{b}"),
            Expr::Div(a, b) => write!(f, "{a}/{b}"),
            Expr::Sqrt(e) => write!(f, "sqrt({e})"),
        }
    }
}

struct Parser<'a> {
    text: &'a str,
    pos: usize,
    /// Open parentheses, square roots and signs around the current position.
    depth: usize,
    /// Binary operations read so far.
    operations: usize,
}

/// Deepest nesting of parentheses, square roots and signs an expression may have.
pub const MAX_NESTING: usize = 200;

/// Most binary operations (`+ - * /`) an expression may have: each adds a
/// level to the tree that evaluation walks recursively, so a long flat sum
/// is bounded like deep nesting (a generated automaton's entries have tens).
pub const MAX_OPERATIONS: usize = 1000;

impl Parser<'_> {
    fn error(&self, expected: &str) -> ExprSyntaxError {
        let found = match self.text[self.pos..].chars().next() {
            Some(c) => format!("`{c}`"),
            None => "the end of the expression".to_string(),
        };
        ExprSyntaxError { offset: self.pos, message: format!("found {found}, expected {expected}") }
    }

    fn skip_ws(&mut self) {
        while self.text[self.pos..].starts_with(char::is_whitespace) {
            self.pos += self.text[self.pos..].chars().next().map_or(1, char::len_utf8);
        }
    }

    fn eat(&mut self, c: char) -> bool {
        self.skip_ws();
        if self.text[self.pos..].starts_with(c) {
            self.pos += c.len_utf8();
            true
        } else {
            false
        }
    }

    /// Counts one more binary operation, refusing more than [`MAX_OPERATIONS`].
    fn operation(&mut self) -> Result<(), ExprSyntaxError> {
        self.operations += 1;
        if self.operations > MAX_OPERATIONS {
            return Err(ExprSyntaxError {
                offset: self.pos,
                message: format!("the expression has more than {MAX_OPERATIONS} operations (+ - * /)"),
            });
        }
        Ok(())
    }

    fn expr(&mut self) -> Result<Expr, ExprSyntaxError> {
        let mut left = self.term()?;
        loop {
            if self.eat('+') {
                self.operation()?;
                left = Expr::Add(Box::new(left), Box::new(self.term()?));
            } else if self.eat('-') {
                self.operation()?;
                left = Expr::Sub(Box::new(left), Box::new(self.term()?));
            } else {
                return Ok(left);
            }
        }
    }

    fn term(&mut self) -> Result<Expr, ExprSyntaxError> {
        let mut left = self.unary()?;
        loop {
            if self.eat('*') || self.eat('·') {
                self.operation()?;
                left = Expr::Mul(Box::new(left), Box::new(self.unary()?));
            } else if self.eat('/') {
                self.operation()?;
                left = Expr::Div(Box::new(left), Box::new(self.unary()?));
            } else {
                return Ok(left);
            }
        }
    }

    fn unary(&mut self) -> Result<Expr, ExprSyntaxError> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(ExprSyntaxError {
                offset: self.pos,
                message: format!("the expression is nested more than {MAX_NESTING} levels deep"),
            });
        }
        let e = if self.eat('-') {
            Ok(Expr::Neg(Box::new(self.unary()?)))
        } else if self.eat('+') {
            self.unary()
        } else {
            self.atom()
        };
        self.depth -= 1;
        e
    }

    fn take_while(&mut self, f: impl Fn(char) -> bool) -> &str {
        let start = self.pos;
        while let Some(c) = self.text[self.pos..].chars().next().filter(|c| f(*c)) {
            self.pos += c.len_utf8();
        }
        &self.text[start..self.pos]
    }

    fn index(&mut self) -> Result<usize, ExprSyntaxError> {
        self.skip_ws();
        let digits = self.take_while(|c| c.is_ascii_digit()).to_string();
        let index = digits.parse().map_err(|_| self.error("an index (0, 1, 2, ...)"))?;
        if !self.eat(']') {
            return Err(self.error("`]`"));
        }
        Ok(index)
    }

    fn atom(&mut self) -> Result<Expr, ExprSyntaxError> {
        self.skip_ws();
        let start = self.pos;
        let Some(c) = self.text[self.pos..].chars().next() else {
            return Err(self.error("a number, a name or `(`"));
        };
        if c == '(' {
            self.pos += 1;
            let e = self.expr()?;
            if !self.eat(')') {
                return Err(self.error("`)`"));
            }
            return Ok(e);
        }
        if c.is_ascii_digit() || c == '.' {
            let mut literal = self.take_while(|c| c.is_ascii_digit() || c == '.').to_string();
            let rest = &self.text[self.pos..];
            let sign_len = rest.get(1..2).filter(|s| *s == "+" || *s == "-").map_or(0, |_| 1);
            if (rest.starts_with('e') || rest.starts_with('E'))
                && rest[1 + sign_len..].starts_with(|c: char| c.is_ascii_digit())
            {
                literal.push_str(&rest[..1 + sign_len]);
                self.pos += 1 + sign_len;
                literal.push_str(self.take_while(|c| c.is_ascii_digit()));
            }
            return Num::parse_decimal(&literal).map(Expr::Num).ok_or(ExprSyntaxError {
                offset: start,
                message: format!("`{literal}` is not a number (or its exponent is beyond ±{MAX_EXPONENT})"),
            });
        }
        if c.is_alphabetic() || c == '_' {
            let name = self.take_while(|c| c.is_alphanumeric() || c == '_').to_string();
            if name == "sqrt" && self.eat('(') {
                let e = self.expr()?;
                if !self.eat(')') {
                    return Err(self.error("`)`"));
                }
                return Ok(Expr::Sqrt(Box::new(e)));
            }
            let save = self.pos;
            if self.eat('[') {
                let row = self.index()?;
                if !self.eat('[') {
                    return Err(self.error("`[` and a column index"));
                }
                let col = self.index()?;
                return Ok(Expr::Entry { arrow: name, row, col, offset: start });
            }
            self.pos = save;
            return Ok(Expr::Param(name, start));
        }
        Err(self.error("a number, a name or `(`"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoNames;
    impl Env<f64> for NoNames {
        fn param(&self, name: &str) -> Option<f64> {
            (name == "a").then_some(0.25)
        }
        fn entry(&self, arrow: &str, row: usize, col: usize) -> Option<f64> {
            (arrow == "T0" && row == 1 && col == 0).then_some(2.0)
        }
    }

    fn eval(text: &str) -> f64 {
        Expr::parse(text).unwrap().eval(&NoNames).unwrap()
    }

    #[test]
    fn evaluates_with_precedence() {
        assert_eq!(eval("1 - a"), 0.75);
        assert_eq!(eval("-1/16"), -0.0625);
        assert_eq!(eval("2 * (1 + 3) / 4"), 2.0);
        assert!((eval("sqrt(3)/6") - 3f64.sqrt() / 6.0).abs() < 1e-16);
        assert_eq!(eval("T0[1][0] - 1e-1"), 1.9);
        assert_eq!(eval("- -2"), 2.0);
    }

    #[test]
    fn syntax_errors_have_offsets() {
        let e = Expr::parse("1 - * a").unwrap_err();
        assert_eq!(e.offset, 4);
        assert!(e.message.contains("expected a number"), "{}", e.message);
        assert_eq!(Expr::parse("(1 + 2").unwrap_err().offset, 6);
        assert_eq!(Expr::parse("T0[1][x]").unwrap_err().offset, 6);
        assert_eq!(Expr::parse("1 2").unwrap_err().offset, 2);
    }
}
