//! Requirement formulas: a small signal temporal logic over recorded signals.
//!
//! ```text
//! formula    := until
//! until      := or ( "until" interval or )?
//! or         := and ( "or" and )*
//! and        := unary ( "and" unary )*
//! unary      := "not" unary | ("always" | "eventually") interval unary
//!             | "(" formula ")" | comparison
//! interval   := "[" number "," number "]"          (seconds, relative to now)
//! comparison := expr ("<" | "<=" | ">" | ">=") expr
//! expr       := term (("+" | "-") term)*
//! term       := factor (("*" | "/") factor)*
//! factor     := number | signal | "abs" "(" expr ")" | "sqrt" "(" expr ")"
//!             | "hypot" "(" expr "," expr ")" | "(" expr ")" | "-" factor
//! signal     := instance.variable, with [k] for an array element (plant.r_nue[2])
//! ```
//!
//! A parse error names the character position where the formula stops making sense.

/// A numeric expression over the recorded signals at one sample.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    Number(f64),
    /// A recorded column, `instance.variable`.
    Signal(String),
    Neg(Box<Expr>),
    Abs(Box<Expr>),
    Sqrt(Box<Expr>),
    Hypot(Box<Expr>, Box<Expr>),
    Binary(Box<Expr>, Op, Box<Expr>),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    Add,
    Sub,
    Mul,
    Div,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Comparison {
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
}

/// A time window `[from, to]` in seconds after the time of evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub from_s: f64,
    pub to_s: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Formula {
    Compare(Expr, Comparison, Expr),
    Not(Box<Formula>),
    And(Box<Formula>, Box<Formula>),
    Or(Box<Formula>, Box<Formula>),
    Always(Interval, Box<Formula>),
    Eventually(Interval, Box<Formula>),
    Until(Box<Formula>, Interval, Box<Formula>),
}

impl Formula {
    /// Every signal the formula reads, in order of appearance, each once.
    pub fn signals(&self) -> Vec<&str> {
        let mut out = Vec::new();
        self.collect(&mut out);
        out
    }

    /// How far past a sample the formula's robustness there looks (s): the samples after
    /// `t + horizon` cannot change its value at `t` (a comparison reads its own sample only;
    /// a window adds its end). Infinite for an unbounded window.
    pub fn horizon_s(&self) -> f64 {
        match self {
            Formula::Compare(..) => 0.0,
            Formula::Not(f) => f.horizon_s(),
            Formula::And(a, b) | Formula::Or(a, b) => a.horizon_s().max(b.horizon_s()),
            Formula::Always(w, f) | Formula::Eventually(w, f) => w.to_s + f.horizon_s(),
            Formula::Until(a, w, b) => w.to_s + a.horizon_s().max(b.horizon_s()),
        }
    }

    fn collect<'a>(&'a self, out: &mut Vec<&'a str>) {
        match self {
            Formula::Compare(a, _, b) => {
                a.collect(out);
                b.collect(out);
            }
            Formula::Not(f) | Formula::Always(_, f) | Formula::Eventually(_, f) => f.collect(out),
            Formula::And(a, b) | Formula::Or(a, b) | Formula::Until(a, _, b) => {
                a.collect(out);
                b.collect(out);
            }
        }
    }
}

impl Expr {
    fn collect<'a>(&'a self, out: &mut Vec<&'a str>) {
        match self {
            Expr::Number(_) => {}
            Expr::Signal(name) => {
                if !out.contains(&name.as_str()) {
                    out.push(name);
                }
            }
            Expr::Neg(e) | Expr::Abs(e) | Expr::Sqrt(e) => e.collect(out),
            Expr::Binary(a, _, b) | Expr::Hypot(a, b) => {
                a.collect(out);
                b.collect(out);
            }
        }
    }
}

/// Why a formula does not parse: what was expected, at which character (1-based).
#[derive(Debug, Clone, PartialEq)]
pub struct ParseError {
    pub position: usize,
    pub message: String,
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "at character {}: {}", self.position, self.message)
    }
}

/// The character position (1-based) where `signal` first appears in the formula `text`, as
/// a parse error gives it.
pub fn signal_position(text: &str, signal: &str) -> Option<usize> {
    tokens(text)
        .ok()?
        .into_iter()
        .find(|(_, token)| matches!(token, Token::Word(w) if w == signal))
        .map(|(at, _)| at)
}

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Number(f64),
    Word(String),
    Symbol(&'static str),
}

/// Tokens with their 1-based character positions.
fn tokens(text: &str) -> Result<Vec<(usize, Token)>, ParseError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let at = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            let start = i;
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric()
                    || chars[i] == '.'
                    || ((chars[i] == '-' || chars[i] == '+') && matches!(chars[i - 1], 'e' | 'E')))
            {
                i += 1;
            }
            let literal: String = chars[start..i].iter().collect();
            let value = literal.parse().map_err(|_| ParseError {
                position: at,
                message: format!("{literal:?} is not a number"),
            })?;
            out.push((at, Token::Number(value)));
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            // A signal name: words joined by dots, with [k] element indices.
            while i < chars.len()
                && (chars[i].is_alphanumeric() || matches!(chars[i], '_' | '.' | '[' | ']'))
            {
                // `[` starts an index only right after a name character, so `always [0, 1]`
                // keeps its interval.
                if chars[i] == '[' && !chars[i - 1].is_alphanumeric() && chars[i - 1] != '_' {
                    break;
                }
                if chars[i] == '[' && !chars[start..i].contains(&'.') {
                    break;
                }
                i += 1;
            }
            out.push((at, Token::Word(chars[start..i].iter().collect())));
        } else {
            let two: String = chars[i..(i + 2).min(chars.len())].iter().collect();
            let symbol = ["<=", ">="]
                .into_iter()
                .find(|s| two == *s)
                .or_else(|| {
                    ["<", ">", "(", ")", "[", "]", ",", "+", "-", "*", "/"]
                        .into_iter()
                        .find(|s| s.starts_with(c))
                })
                .ok_or_else(|| ParseError {
                    position: at,
                    message: format!("unexpected character {c:?}"),
                })?;
            i += symbol.len();
            out.push((at, Token::Symbol(symbol)));
        }
    }
    Ok(out)
}

struct Parser {
    tokens: Vec<(usize, Token)>,
    next: usize,
    end: usize,
}

/// Parses a requirement formula.
pub fn parse(text: &str) -> Result<Formula, ParseError> {
    let mut p = Parser {
        tokens: tokens(text)?,
        next: 0,
        end: text.chars().count() + 1,
    };
    let formula = p.until()?;
    if p.next < p.tokens.len() {
        return Err(p.error("an operator (and, or, until) or the end of the formula"));
    }
    Ok(formula)
}

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.next).map(|(_, t)| t)
    }

    fn position(&self) -> usize {
        self.tokens.get(self.next).map_or(self.end, |(at, _)| *at)
    }

    fn error(&self, expected: &str) -> ParseError {
        let found = match self.peek() {
            None => "the end of the formula".to_owned(),
            Some(Token::Number(x)) => format!("the number {x}"),
            Some(Token::Word(w)) => format!("{w:?}"),
            Some(Token::Symbol(s)) => format!("{s:?}"),
        };
        ParseError {
            position: self.position(),
            message: format!("expected {expected}, found {found}"),
        }
    }

    fn word(&mut self, word: &str) -> bool {
        if matches!(self.peek(), Some(Token::Word(w)) if w == word) {
            self.next += 1;
            true
        } else {
            false
        }
    }

    fn symbol(&mut self, symbol: &str) -> bool {
        if matches!(self.peek(), Some(Token::Symbol(s)) if *s == symbol) {
            self.next += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, symbol: &str) -> Result<(), ParseError> {
        if self.symbol(symbol) {
            Ok(())
        } else {
            Err(self.error(&format!("{symbol:?}")))
        }
    }

    fn until(&mut self) -> Result<Formula, ParseError> {
        let left = self.or()?;
        if self.word("until") {
            let interval = self.interval()?;
            let right = self.or()?;
            return Ok(Formula::Until(Box::new(left), interval, Box::new(right)));
        }
        Ok(left)
    }

    fn or(&mut self) -> Result<Formula, ParseError> {
        let mut left = self.and()?;
        while self.word("or") {
            left = Formula::Or(Box::new(left), Box::new(self.and()?));
        }
        Ok(left)
    }

    fn and(&mut self) -> Result<Formula, ParseError> {
        let mut left = self.unary()?;
        while self.word("and") {
            left = Formula::And(Box::new(left), Box::new(self.unary()?));
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Formula, ParseError> {
        if self.word("not") {
            return Ok(Formula::Not(Box::new(self.unary()?)));
        }
        if self.word("always") {
            let interval = self.interval()?;
            return Ok(Formula::Always(interval, Box::new(self.unary()?)));
        }
        if self.word("eventually") {
            let interval = self.interval()?;
            return Ok(Formula::Eventually(interval, Box::new(self.unary()?)));
        }
        if matches!(self.peek(), Some(Token::Symbol("("))) {
            // A parenthesised formula, or a comparison that starts with a parenthesised
            // expression: try the formula first.
            let start = self.next;
            self.next += 1;
            if let Ok(inner) = self.until() {
                if self.symbol(")") && !self.at_comparison_continuation() {
                    return Ok(inner);
                }
            }
            self.next = start;
        }
        self.comparison()
    }

    /// Whether the next token continues an expression or comparison (so the parenthesis
    /// just closed was an expression's).
    fn at_comparison_continuation(&self) -> bool {
        matches!(
            self.peek(),
            Some(Token::Symbol(
                "<" | "<=" | ">" | ">=" | "+" | "-" | "*" | "/"
            ))
        )
    }

    fn interval(&mut self) -> Result<Interval, ParseError> {
        self.expect("[")?;
        let from_s = self.number()?;
        self.expect(",")?;
        let to_s = self.number()?;
        let at = self.position();
        self.expect("]")?;
        if !(from_s >= 0.0 && to_s >= from_s) {
            return Err(ParseError {
                position: at,
                message: format!(
                    "the interval [{from_s}, {to_s}] must have 0 <= start <= end (seconds)"
                ),
            });
        }
        Ok(Interval { from_s, to_s })
    }

    fn number(&mut self) -> Result<f64, ParseError> {
        let negative = self.symbol("-");
        match self.peek() {
            Some(Token::Number(x)) => {
                let x = *x;
                self.next += 1;
                Ok(if negative { -x } else { x })
            }
            _ => Err(self.error("a number")),
        }
    }

    fn comparison(&mut self) -> Result<Formula, ParseError> {
        let left = self.expr()?;
        let op = match self.peek() {
            Some(Token::Symbol("<")) => Comparison::Less,
            Some(Token::Symbol("<=")) => Comparison::LessEqual,
            Some(Token::Symbol(">")) => Comparison::Greater,
            Some(Token::Symbol(">=")) => Comparison::GreaterEqual,
            _ => return Err(self.error("a comparison (<, <=, >, >=)")),
        };
        self.next += 1;
        let right = self.expr()?;
        Ok(Formula::Compare(left, op, right))
    }

    fn expr(&mut self) -> Result<Expr, ParseError> {
        let mut left = self.term()?;
        loop {
            let op = if self.symbol("+") {
                Op::Add
            } else if self.symbol("-") {
                Op::Sub
            } else {
                return Ok(left);
            };
            left = Expr::Binary(Box::new(left), op, Box::new(self.term()?));
        }
    }

    fn term(&mut self) -> Result<Expr, ParseError> {
        let mut left = self.factor()?;
        loop {
            let op = if self.symbol("*") {
                Op::Mul
            } else if self.symbol("/") {
                Op::Div
            } else {
                return Ok(left);
            };
            left = Expr::Binary(Box::new(left), op, Box::new(self.factor()?));
        }
    }

    fn factor(&mut self) -> Result<Expr, ParseError> {
        if self.symbol("-") {
            return Ok(Expr::Neg(Box::new(self.factor()?)));
        }
        if self.symbol("(") {
            let inner = self.expr()?;
            self.expect(")")?;
            return Ok(inner);
        }
        match self.peek().cloned() {
            Some(Token::Number(x)) => {
                self.next += 1;
                Ok(Expr::Number(x))
            }
            Some(Token::Word(w)) if w == "abs" || w == "sqrt" => {
                self.next += 1;
                self.expect("(")?;
                let inner = Box::new(self.expr()?);
                self.expect(")")?;
                Ok(if w == "abs" {
                    Expr::Abs(inner)
                } else {
                    Expr::Sqrt(inner)
                })
            }
            Some(Token::Word(w)) if w == "hypot" => {
                self.next += 1;
                self.expect("(")?;
                let a = self.expr()?;
                self.expect(",")?;
                let b = self.expr()?;
                self.expect(")")?;
                Ok(Expr::Hypot(Box::new(a), Box::new(b)))
            }
            Some(Token::Word(w))
                if w.contains('.') && !matches!(w.as_str(), "always" | "eventually") =>
            {
                self.next += 1;
                Ok(Expr::Signal(w))
            }
            _ => Err(self.error(
                "a number, a signal (instance.variable), abs(...), sqrt(...) or hypot(..., ...)",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issue_examples_parse_into_the_expected_trees() {
        let f = parse("always [30, 172] abs(gnc.err_tilt) < 0.035").unwrap();
        assert_eq!(
            f,
            Formula::Always(
                Interval {
                    from_s: 30.0,
                    to_s: 172.0
                },
                Box::new(Formula::Compare(
                    Expr::Abs(Box::new(Expr::Signal("gnc.err_tilt".into()))),
                    Comparison::Less,
                    Expr::Number(0.035)
                ))
            )
        );
        let f = parse("always [0, 100] plant.r_nue[2] > 700").unwrap();
        assert_eq!(f.signals(), ["plant.r_nue[2]"]);
        let f = parse("plant.mass > 700 until [0, 50] eventually [0, 5] gnc.guidance_phase >= 2")
            .unwrap();
        assert!(matches!(f, Formula::Until(..)), "{f:?}");
        let f = parse("always [12, 142] hypot(plant.r[1], sqrt(plant.r[3] * plant.r[3])) < 20")
            .unwrap();
        assert_eq!(f.signals(), ["plant.r[1]", "plant.r[3]"]);
        let f = parse("(plant.a + 2) * 3 <= 1e-3 and not (plant.b > 0 or plant.c < -1)").unwrap();
        assert!(matches!(f, Formula::And(..)), "{f:?}");
        assert_eq!(f.signals(), ["plant.a", "plant.b", "plant.c"]);
    }

    #[test]
    fn a_bad_formula_names_the_position_and_what_was_expected() {
        for (text, position, expected) in [
            ("always [0, 100 plant.x > 1", 16, "expected \"]\""),
            ("always [5, 1] plant.x > 1", 13, "0 <= start <= end"),
            ("plant.x >", 10, "expected a number, a signal"),
            ("plant.x = 3", 9, "unexpected character '='"),
            ("plant.x > 1 plant.y < 2", 13, "an operator"),
            ("eventually plant.x > 1", 12, "expected \"[\""),
            ("abs(plant.x < 3", 13, "expected \")\""),
            ("x > 1", 1, "a signal (instance.variable)"),
        ] {
            let e = parse(text).unwrap_err();
            assert_eq!(e.position, position, "{text}: {e}");
            assert!(e.message.contains(expected), "{text}: {e}");
        }
    }

    #[test]
    fn a_signal_is_found_where_it_is_written_not_inside_a_longer_name() {
        let text = "always [0, 1] p.xx > 0 and abs(p.x) < 2";
        assert_eq!(signal_position(text, "p.x"), Some(32));
        assert_eq!(signal_position(text, "p.xx"), Some(15));
        assert_eq!(signal_position(text, "p.y"), None);
    }
}
