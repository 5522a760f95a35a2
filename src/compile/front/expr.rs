//! Expression laws: a force written as a formula of the element's elongation
//! `x` (springs) or rate `v` (dampers) and the rig's parameters, e.g.
//! `"k*x + k3*x^3"` or `"c*v*abs(v)"`, parsed here and lowered to the graph.
//!
//! Grammar (usual precedence; `^` binds tighter than unary minus and is
//! right-associative, so `-x^2` is `-(x^2)` and `2^3^2` is `2^9`):
//!
//! ```text
//! expr  := term (("+" | "-") term)*
//! term  := unary (("*" | "/") unary)*
//! unary := "-" unary | power
//! power := atom ("^" unary)?
//! atom  := number | name | name "(" expr ("," expr)* ")" | "(" expr ")"
//! ```
//!
//! `a^n` with a literal integer `|n| ≤ 8` is repeated multiplication (exact for
//! negative `a`); any other exponent gives `|a|^b` (from `exp(b·ln|a|)`, 0 at
//! `a = 0`), as WGSL's `pow` is undefined for negative bases. Functions: `abs`,
//! `sign` (0 at 0), `exp`, `ln`, `sqrt` (of `|a|`), `sin`, `cos`, `tanh`, `min`,
//! `max` and `spow(a, b) = sign(a)·|a|^b`.
//!
//! Limits: a law is at most [`MAX_CHARS`] characters long and nests at most
//! [`MAX_DEPTH`] levels (each parenthesis, sign, exponent and call is one
//! level). Parsing, lowering and dropping a law recurse along its tree; the
//! two limits bound that tree's depth (a chain of `+` or `*` is as deep as it
//! is long) well within any thread's stack.

use crate::compile::ir::{Graph, Id, Op};

/// Most characters a law may have.
pub const MAX_CHARS: usize = 2000;

/// Deepest nesting a law may have: parentheses, unary signs, exponents and
/// function calls, each one level.
pub const MAX_DEPTH: usize = 64;

/// A parse or lowering error at a 1-based character column of the expression.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExprError {
    /// 1-based column (characters).
    pub column: usize,
    /// What is wrong there.
    pub message: String,
}

/// A function an expression may call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    /// `abs(a)`.
    Abs,
    /// `sign(a)`.
    Sign,
    /// `exp(a)`.
    Exp,
    /// `ln(a)`.
    Ln,
    /// `sqrt(|a|)`.
    Sqrt,
    /// `sin(a)`.
    Sin,
    /// `cos(a)`.
    Cos,
    /// `tanh(a)`.
    Tanh,
    /// `min(a, b)`.
    Min,
    /// `max(a, b)`.
    Max,
    /// `spow(a, b)`.
    Spow,
}

const FUNCS: [(&str, Func, usize); 11] = [
    ("abs", Func::Abs, 1),
    ("sign", Func::Sign, 1),
    ("exp", Func::Exp, 1),
    ("ln", Func::Ln, 1),
    ("sqrt", Func::Sqrt, 1),
    ("sin", Func::Sin, 1),
    ("cos", Func::Cos, 1),
    ("tanh", Func::Tanh, 1),
    ("min", Func::Min, 2),
    ("max", Func::Max, 2),
    ("spow", Func::Spow, 2),
];

/// A parsed expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A literal.
    Num(f64),
    /// A variable or parameter name, with its column.
    Name(String, usize),
    /// `−a`.
    Neg(Box<Expr>),
    /// `a op b` with op one of `+ − * /`.
    Bin(char, Box<Expr>, Box<Expr>),
    /// `a ^ b`.
    Pow(Box<Expr>, Box<Expr>),
    /// A function call.
    Call(Func, Vec<Expr>),
}

/// A part of a law that is not a finite number (see
/// [`Expr::fixed_part_not_finite`]).
#[derive(Debug, Clone, PartialEq)]
pub struct NotFinite {
    /// The part, written out with its parentheses (`(0 / 0)`).
    pub part: String,
    /// The variable's value where it is not finite.
    pub at: f64,
    /// Its value there (NaN or ±∞).
    pub value: f64,
    /// Whether the part is a division by a part that is 0 there.
    pub division: bool,
}

impl std::fmt::Display for Expr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Expr::Num(v) => write!(f, "{v}"),
            Expr::Name(n, _) => f.write_str(n),
            Expr::Neg(a) => write!(f, "-{a}"),
            Expr::Bin(op, a, b) => write!(f, "({a} {op} {b})"),
            Expr::Pow(a, b) => write!(f, "{a}^{b}"),
            Expr::Call(func, args) => {
                let name = FUNCS
                    .iter()
                    .find(|(_, g, _)| g == func)
                    .map_or("?", |(n, ..)| *n);
                write!(f, "{name}(")?;
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "{a}")?;
                }
                f.write_str(")")
            }
        }
    }
}

struct Parser<'a> {
    chars: Vec<char>,
    pos: usize,
    src: &'a str,
    /// Levels of nesting open at `pos` (see [`MAX_DEPTH`]).
    depth: usize,
}

fn err(column: usize, message: impl Into<String>) -> ExprError {
    ExprError {
        column,
        message: message.into(),
    }
}

impl Parser<'_> {
    fn skip(&mut self) {
        while self.pos < self.chars.len() && self.chars[self.pos].is_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<char> {
        self.skip();
        self.chars.get(self.pos).copied()
    }

    fn col(&self) -> usize {
        self.pos + 1
    }

    fn expect(&mut self, c: char) -> Result<(), ExprError> {
        match self.peek() {
            Some(x) if x == c => {
                self.pos += 1;
                Ok(())
            }
            Some(x) => Err(err(self.col(), format!("expected '{c}', found '{x}'"))),
            None => Err(err(self.col(), format!("expected '{c}', found the end"))),
        }
    }

    fn expr(&mut self) -> Result<Expr, ExprError> {
        self.chain(['+', '-'], Self::term)
    }

    fn term(&mut self) -> Result<Expr, ExprError> {
        self.chain(['*', '/'], Self::unary)
    }

    /// `operand (op operand)*` for the two operators `ops` of one precedence
    /// level, grouped from the left.
    fn chain(
        &mut self,
        ops: [char; 2],
        operand: fn(&mut Self) -> Result<Expr, ExprError>,
    ) -> Result<Expr, ExprError> {
        let mut a = operand(self)?;
        while let Some(op) = self.peek().filter(|c| ops.contains(c)) {
            self.pos += 1;
            let b = operand(self)?;
            a = Expr::Bin(op, Box::new(a), Box::new(b));
        }
        Ok(a)
    }

    /// Every level of nesting passes here, so the depth is counted here.
    fn unary(&mut self) -> Result<Expr, ExprError> {
        if self.depth >= MAX_DEPTH {
            return Err(err(
                self.col(),
                format!(
                    "nested deeper than {MAX_DEPTH} levels (parentheses, signs, exponents and calls)"
                ),
            ));
        }
        self.depth += 1;
        let r = self.unary_within();
        self.depth -= 1;
        r
    }

    fn unary_within(&mut self) -> Result<Expr, ExprError> {
        if self.peek() == Some('-') {
            self.pos += 1;
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        if self.peek() == Some('+') {
            self.pos += 1;
            return self.unary();
        }
        let a = self.atom()?;
        if self.peek() == Some('^') {
            self.pos += 1;
            let b = self.unary()?;
            return Ok(Expr::Pow(Box::new(a), Box::new(b)));
        }
        Ok(a)
    }

    fn atom(&mut self) -> Result<Expr, ExprError> {
        let col = self.col();
        match self.peek() {
            None => Err(err(col, "expected a number, a name or '(', found the end")),
            Some('(') => {
                self.pos += 1;
                let e = self.expr()?;
                self.expect(')')?;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => self.number(),
            Some(c) if c.is_alphabetic() || c == '_' => {
                let start = self.pos;
                while self.pos < self.chars.len()
                    && (self.chars[self.pos].is_alphanumeric() || self.chars[self.pos] == '_')
                {
                    self.pos += 1;
                }
                let name: String = self.chars[start..self.pos].iter().collect();
                if self.peek() != Some('(') {
                    return Ok(Expr::Name(name, start + 1));
                }
                let Some(&(_, f, arity)) = FUNCS.iter().find(|(n, ..)| *n == name) else {
                    let known: Vec<&str> = FUNCS.iter().map(|(n, ..)| *n).collect();
                    return Err(err(
                        start + 1,
                        format!("unknown function '{name}' (known: {})", known.join(", ")),
                    ));
                };
                self.pos += 1;
                let mut args = vec![self.expr()?];
                while self.peek() == Some(',') {
                    self.pos += 1;
                    args.push(self.expr()?);
                }
                self.expect(')')?;
                if args.len() != arity {
                    return Err(err(
                        start + 1,
                        format!(
                            "'{name}' takes {arity} argument{}, found {}",
                            if arity == 1 { "" } else { "s" },
                            args.len()
                        ),
                    ));
                }
                Ok(Expr::Call(f, args))
            }
            Some(c) => Err(err(
                col,
                format!("expected a number, a name or '(', found '{c}'"),
            )),
        }
    }

    fn number(&mut self) -> Result<Expr, ExprError> {
        let start = self.pos;
        let digits = |p: &mut Self| {
            while p.pos < p.chars.len()
                && (p.chars[p.pos].is_ascii_digit() || p.chars[p.pos] == '.')
            {
                p.pos += 1;
            }
        };
        digits(self);
        if self.pos < self.chars.len() && matches!(self.chars[self.pos], 'e' | 'E') {
            let save = self.pos;
            self.pos += 1;
            if self.pos < self.chars.len() && matches!(self.chars[self.pos], '+' | '-') {
                self.pos += 1;
            }
            if self.pos < self.chars.len() && self.chars[self.pos].is_ascii_digit() {
                digits(self);
            } else {
                self.pos = save;
            }
        }
        let text: String = self.chars[start..self.pos].iter().collect();
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .map(Expr::Num)
            .ok_or_else(|| err(start + 1, format!("'{text}' is not a number")))
    }
}

/// Parses `src`.
pub fn parse(src: &str) -> Result<Expr, ExprError> {
    let chars: Vec<char> = src.chars().collect();
    if chars.len() > MAX_CHARS {
        return Err(err(
            MAX_CHARS + 1,
            format!(
                "a law of at most {MAX_CHARS} characters, found {} characters",
                chars.len()
            ),
        ));
    }
    let mut p = Parser {
        chars,
        pos: 0,
        src,
        depth: 0,
    };
    let e = p.expr()?;
    match p.peek() {
        None => Ok(e),
        Some(c) => Err(err(
            p.col(),
            format!(
                "unexpected '{c}' after a complete expression in \"{}\"",
                p.src
            ),
        )),
    }
}

/// `a^n` for a literal integer exponent, if it is one that multiplication covers.
fn small_integer(e: &Expr) -> Option<i32> {
    let v = match e {
        Expr::Num(v) => *v,
        Expr::Neg(a) => match **a {
            Expr::Num(v) => -v,
            _ => return None,
        },
        _ => return None,
    };
    (v.fract() == 0.0 && v.abs() <= 8.0).then_some(v as i32)
}

impl Expr {
    /// Lowers to `g`; `name` resolves a name (the variable or a parameter) to
    /// its value, or says why it cannot.
    pub fn lower(
        &self,
        g: &mut Graph,
        name: &mut dyn FnMut(&mut Graph, &str) -> Result<Id, String>,
    ) -> Result<Id, ExprError> {
        Ok(match self {
            Expr::Num(v) => g.c(*v),
            Expr::Name(n, col) => name(g, n).map_err(|m| err(*col, m))?,
            Expr::Neg(a) => {
                let a = a.lower(g, name)?;
                g.neg(a)
            }
            Expr::Bin(op, a, b) => {
                let (a, b) = (a.lower(g, name)?, b.lower(g, name)?);
                match op {
                    '+' => g.add(a, b),
                    '-' => g.sub(a, b),
                    '*' => g.mul(a, b),
                    _ => g.div(a, b),
                }
            }
            Expr::Pow(a, b) => {
                let base = a.lower(g, name)?;
                if let Some(n) = small_integer(b) {
                    let mut r = g.c(1.0);
                    for _ in 0..n.unsigned_abs() {
                        r = g.mul(r, base);
                    }
                    if n < 0 {
                        let one = g.c(1.0);
                        r = g.div(one, r);
                    }
                    r
                } else {
                    let p = b.lower(g, name)?;
                    let abs = g.push(Op::Abs(base));
                    g.signed_pow(abs, p)
                }
            }
            Expr::Call(f, args) => {
                let mut v = Vec::with_capacity(args.len());
                for a in args {
                    v.push(a.lower(g, name)?);
                }
                let zero = g.c(0.0);
                let one = g.c(1.0);
                match f {
                    Func::Abs => g.push(Op::Abs(v[0])),
                    Func::Sign => {
                        let m1 = g.c(-1.0);
                        let neg = g.le(v[0], zero);
                        let s = g.select(neg, m1, one);
                        let is_zero = g.eq(v[0], zero);
                        g.select(is_zero, zero, s)
                    }
                    Func::Exp => g.push(Op::Exp(v[0])),
                    Func::Ln => g.push(Op::Ln(v[0])),
                    Func::Sqrt => {
                        let abs = g.push(Op::Abs(v[0]));
                        let half = g.c(0.5);
                        g.signed_pow(abs, half)
                    }
                    Func::Sin => g.push(Op::Sin(v[0])),
                    Func::Cos => g.push(Op::Cos(v[0])),
                    Func::Tanh => {
                        // tanh a = expm1(2a) / (expm1(2a) + 2), with |2a| capped
                        // at 40 (tanh is ±1 to f64 there) so exp never overflows.
                        let two = g.c(2.0);
                        let lim = g.c(40.0);
                        let a2 = g.mul(two, v[0]);
                        let hi = g.push(Op::Min(a2, lim));
                        let nlim = g.c(-40.0);
                        let a2 = g.push(Op::Max(hi, nlim));
                        let e = g.push(Op::Expm1(a2));
                        let den = g.add(e, two);
                        g.div(e, den)
                    }
                    Func::Min => g.push(Op::Min(v[0], v[1])),
                    Func::Max => g.push(Op::Max(v[0], v[1])),
                    Func::Spow => g.signed_pow(v[0], v[1]),
                }
            }
        })
    }

    /// Its value, with `name` giving each name's value (for the stability
    /// bound's tangent estimate and the finiteness checks). As the lowered
    /// graph computes it: `|a|^b` and `spow` are 0 at `a = 0`.
    pub fn eval(&self, name: &dyn Fn(&str) -> f64) -> f64 {
        match self {
            Expr::Num(v) => *v,
            Expr::Name(n, _) => name(n),
            _ => {
                let kids: Vec<f64> = self.children().iter().map(|a| a.eval(name)).collect();
                self.apply(&kids)
            }
        }
    }

    /// The parts it is made of, in order.
    fn children(&self) -> Vec<&Expr> {
        match self {
            Expr::Num(_) | Expr::Name(..) => vec![],
            Expr::Neg(a) => vec![a],
            Expr::Bin(_, a, b) | Expr::Pow(a, b) => vec![a, b],
            Expr::Call(_, args) => args.iter().collect(),
        }
    }

    /// Its value from its parts' values `v` (not for a number or a name).
    fn apply(&self, v: &[f64]) -> f64 {
        // `|a|^b` as `signed_pow` lowers it: 0 at `a = 0`, whatever `b`.
        let pow = |a: f64, b: f64| if a == 0.0 { 0.0 } else { a.abs().powf(b) };
        match self {
            Expr::Num(x) => *x,
            Expr::Name(..) => f64::NAN,
            Expr::Neg(_) => -v[0],
            Expr::Bin(op, ..) => match op {
                '+' => v[0] + v[1],
                '-' => v[0] - v[1],
                '*' => v[0] * v[1],
                _ => v[0] / v[1],
            },
            Expr::Pow(_, b) => match small_integer(b) {
                Some(n) => v[0].powi(n),
                None => pow(v[0], v[1]),
            },
            Expr::Call(f, _) => match f {
                Func::Abs => v[0].abs(),
                Func::Sign if v[0] == 0.0 => 0.0,
                Func::Sign => v[0].signum(),
                Func::Exp => v[0].exp(),
                Func::Ln => v[0].ln(),
                Func::Sqrt => v[0].abs().sqrt(),
                Func::Sin => v[0].sin(),
                Func::Cos => v[0].cos(),
                Func::Tanh => v[0].tanh(),
                Func::Min => v[0].min(v[1]),
                Func::Max => v[0].max(v[1]),
                Func::Spow => v[0].signum() * pow(v[0], v[1]),
            },
        }
    }

    /// The first part (innermost first) that reads no parameter — only `var`
    /// and numbers — and is not finite for some `var` in `xs`, or a division
    /// by such a part that is 0 there. Such a part is not finite whatever
    /// the parameters are.
    pub fn fixed_part_not_finite(&self, var: &str, xs: &[f64]) -> Option<NotFinite> {
        let mut found = None;
        self.fixed_values(var, xs, &mut found);
        found
    }

    /// Its values at `xs` where it reads no parameter; records the first
    /// part not finite in `found`.
    fn fixed_values(
        &self,
        var: &str,
        xs: &[f64],
        found: &mut Option<NotFinite>,
    ) -> Option<Vec<f64>> {
        let values = match self {
            Expr::Num(v) => Some(vec![*v; xs.len()]),
            Expr::Name(n, _) => (n == var).then(|| xs.to_vec()),
            _ => {
                let kids: Vec<Option<Vec<f64>>> = self
                    .children()
                    .iter()
                    .map(|a| a.fixed_values(var, xs, found))
                    .collect();
                if let (Expr::Bin('/', ..), Some(Some(den))) = (self, kids.get(1))
                    && found.is_none()
                    && let Some(i) = den.iter().position(|d| *d == 0.0)
                {
                    *found = Some(NotFinite {
                        part: self.to_string(),
                        at: xs[i],
                        value: f64::INFINITY,
                        division: true,
                    });
                }
                let kids: Option<Vec<Vec<f64>>> = kids.into_iter().collect();
                kids.map(|k| {
                    (0..xs.len())
                        .map(|i| {
                            let v: Vec<f64> = k.iter().map(|c| c[i]).collect();
                            self.apply(&v)
                        })
                        .collect()
                })
            }
        };
        if let Some(v) = &values
            && found.is_none()
            && let Some(i) = v.iter().position(|x| !x.is_finite())
        {
            *found = Some(NotFinite {
                part: self.to_string(),
                at: xs[i],
                value: v[i],
                division: false,
            });
        }
        values
    }

    /// Every name it reads, with its column.
    pub fn names(&self, out: &mut Vec<(String, usize)>) {
        match self {
            Expr::Num(_) => {}
            Expr::Name(n, c) => out.push((n.clone(), *c)),
            Expr::Neg(a) => a.names(out),
            Expr::Bin(_, a, b) | Expr::Pow(a, b) => {
                a.names(out);
                b.names(out);
            }
            Expr::Call(_, args) => args.iter().for_each(|a| a.names(out)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::ir::eval_op;

    fn value(src: &str, x: f64) -> f64 {
        parse(src).unwrap().eval(&|n| match n {
            "x" => x,
            "k" => 2.0,
            _ => f64::NAN,
        })
    }

    #[test]
    fn precedence_and_associativity_are_the_usual_ones() {
        assert_eq!(value("1 + 2*3", 0.0), 7.0);
        assert_eq!(value("-x^2", 3.0), -9.0);
        assert_eq!(value("2^3^2", 0.0), 512.0);
        assert_eq!(value("(1 + 2) * 3 - 4 / 2", 0.0), 7.0);
        assert_eq!(value("k*x + 1.5e-1*x^3", -2.0), -4.0 - 1.2);
        assert_eq!(value("spow(x, 0.5)", -4.0), -2.0);
        assert_eq!(value("max(x, 1) + min(x, 1) + sign(0) + abs(-x)", 3.0), 7.0);
    }

    #[test]
    fn errors_name_the_column() {
        let e = |s: &str| parse(s).unwrap_err();
        assert_eq!(e("k*x +").column, 6);
        assert_eq!(e("k*x + ) ").column, 7);
        assert_eq!(e("k*x x").column, 5);
        assert!(e("foo(x)").message.contains("unknown function 'foo'"));
        assert!(e("min(x)").message.contains("takes 2 arguments, found 1"));
        assert_eq!(e("2 * $").column, 5);
        assert_eq!(e("(x + 1").column, 7);
    }

    #[test]
    fn lowered_graph_matches_the_direct_evaluation() {
        let src = "k*x + 3*x^3 - spow(x, 1.5) + tanh(x) + sqrt(x) * x^-2 + exp(-x) * ln(2 + x)";
        let e = parse(src).unwrap();
        let mut g = Graph::new();
        let x = g.input(crate::compile::ir::Input::State(0));
        let root = e
            .lower(&mut g, &mut |g, n| match n {
                "x" => Ok(x),
                "k" => Ok(g.c(2.0)),
                other => Err(format!("unknown {other}")),
            })
            .unwrap();
        for xv in [-1.3, -0.2, 0.4, 1.7] {
            let mut vals = vec![0.0; g.ops.len()];
            for (i, op) in g.ops.iter().enumerate() {
                vals[i] = eval_op(*op, |k: Id| vals[k as usize], |_| xv);
            }
            let want = value(src, xv);
            let got = vals[root as usize];
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "x = {xv}: {got} vs {want}"
            );
        }
    }
}
