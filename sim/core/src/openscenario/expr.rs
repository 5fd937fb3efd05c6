//! OpenSCENARIO's expressions, `${...}` (version 1.1 on): numbers, parameter references
//! (`$name`), the arithmetic operators `+ - * / %` with unary minus, the comparisons
//! `== != < <= > >=`, the Boolean `not`, `and`, `or` (with `true` and `false`), parentheses,
//! and the functions of the standard: `round`, `floor`, `ceil`, `sqrt`, `pow`, and from 1.2
//! `sin`, `cos`, `tan`, `asin`, `acos`, `atan`, `sign`, `abs`, `max`, `min`; and esmini's
//! constants `pi` and `e`, which files written for it use. Booleans are
//! 1 and 0. An expression that divides by zero, leaves a function's domain or gives a
//! number that is not finite is refused.

/// How deep parentheses, unary operators and function calls may nest: far beyond any
/// expression a person writes, and short of the stack's end for a mutated file.
const MAX_DEPTH: usize = 64;

/// Evaluates the expression `text` (without its `${` and `}`), looking parameters up with
/// `param`.
pub fn evaluate(text: &str, param: &dyn Fn(&str) -> Result<f64, String>) -> Result<f64, String> {
    let tokens = tokenize(text)?;
    let mut p = Parser {
        tokens,
        at: 0,
        depth: 0,
        param,
    };
    let v = p.or()?;
    if p.at != p.tokens.len() {
        return Err(format!("`{}` after the expression's end", p.tokens[p.at]));
    }
    finite(v)
}

fn finite(v: f64) -> Result<f64, String> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("gives {v}, not a finite number"))
    }
}

/// A token: a number, a parameter (`$name`), a word (function, `and`, `or`, `not`,
/// `true`, `false`) or an operator.
#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(f64),
    Param(String),
    Word(String),
    Op(&'static str),
}

impl std::fmt::Display for Token {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Token::Number(v) => write!(f, "{v}"),
            Token::Param(n) => write!(f, "${n}"),
            Token::Word(w) => write!(f, "{w}"),
            Token::Op(o) => write!(f, "{o}"),
        }
    }
}

const OPERATORS: [&str; 15] = [
    "==", "!=", "<=", ">=", "<", ">", "+", "-", "*", "/", "%", "(", ")", ",", "!",
];

fn tokenize(text: &str) -> Result<Vec<Token>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent: 1e3, 2.5E-2.
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s: String = chars[start..i].iter().collect();
            let v = s
                .parse::<f64>()
                .map_err(|_| format!("`{s}` is not a number"))?;
            out.push(Token::Number(v));
        } else if c == '$' || c.is_alphabetic() || c == '_' {
            let start = if c == '$' { i + 1 } else { i };
            i = start;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let name: String = chars[start..i].iter().collect();
            if name.is_empty() {
                return Err("`$` without a parameter's name".into());
            }
            out.push(if c == '$' {
                Token::Param(name)
            } else {
                Token::Word(name)
            });
        } else {
            let rest: String = chars[i..chars.len().min(i + 2)].iter().collect();
            let op = OPERATORS
                .iter()
                .find(|op| rest.starts_with(**op))
                .ok_or_else(|| format!("`{c}` is not an operator of expressions"))?;
            out.push(Token::Op(op));
            i += op.chars().count();
        }
    }
    Ok(out)
}

struct Parser<'a> {
    tokens: Vec<Token>,
    at: usize,
    depth: usize,
    param: &'a dyn Fn(&str) -> Result<f64, String>,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.at)
    }

    fn eat_op(&mut self, op: &str) -> bool {
        if self.peek()
            == Some(&Token::Op(match OPERATORS.iter().find(|o| **o == op) {
                Some(o) => o,
                None => return false,
            }))
        {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn eat_word(&mut self, word: &str) -> bool {
        if matches!(self.peek(), Some(Token::Word(w)) if w == word) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn deeper(&mut self) -> Result<(), String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            Err(format!("nests deeper than {MAX_DEPTH}"))
        } else {
            Ok(())
        }
    }

    fn or(&mut self) -> Result<f64, String> {
        let mut v = self.and()?;
        while self.eat_word("or") {
            let w = self.and()?;
            v = truth(v != 0.0 || w != 0.0);
        }
        Ok(v)
    }

    fn and(&mut self) -> Result<f64, String> {
        let mut v = self.not()?;
        while self.eat_word("and") {
            let w = self.not()?;
            v = truth(v != 0.0 && w != 0.0);
        }
        Ok(v)
    }

    fn not(&mut self) -> Result<f64, String> {
        if self.eat_word("not") || self.eat_op("!") {
            self.deeper()?;
            let v = self.not()?;
            self.depth -= 1;
            return Ok(truth(v == 0.0));
        }
        self.comparison()
    }

    fn comparison(&mut self) -> Result<f64, String> {
        let v = self.sum()?;
        for op in ["==", "!=", "<=", ">=", "<", ">"] {
            if self.eat_op(op) {
                let w = self.sum()?;
                return Ok(truth(match op {
                    "==" => v == w,
                    "!=" => v != w,
                    "<=" => v <= w,
                    ">=" => v >= w,
                    "<" => v < w,
                    _ => v > w,
                }));
            }
        }
        Ok(v)
    }

    fn sum(&mut self) -> Result<f64, String> {
        let mut v = self.product()?;
        loop {
            if self.eat_op("+") {
                v += self.product()?;
            } else if self.eat_op("-") {
                v -= self.product()?;
            } else {
                return finite(v);
            }
        }
    }

    fn product(&mut self) -> Result<f64, String> {
        let mut v = self.unary()?;
        loop {
            if self.eat_op("*") {
                v *= self.unary()?;
            } else if self.eat_op("/") {
                let w = self.unary()?;
                if w == 0.0 {
                    return Err("divides by zero".into());
                }
                v /= w;
            } else if self.eat_op("%") {
                let w = self.unary()?;
                if w == 0.0 {
                    return Err("takes a remainder by zero".into());
                }
                v %= w;
            } else {
                return finite(v);
            }
        }
    }

    fn unary(&mut self) -> Result<f64, String> {
        if self.eat_op("-") {
            self.deeper()?;
            let v = -self.unary()?;
            self.depth -= 1;
            return Ok(v);
        }
        self.primary()
    }

    fn primary(&mut self) -> Result<f64, String> {
        let token = self
            .peek()
            .cloned()
            .ok_or("ends where a value was expected")?;
        self.at += 1;
        match token {
            Token::Number(v) => Ok(v),
            Token::Param(name) => (self.param)(&name),
            Token::Op("(") => {
                self.deeper()?;
                let v = self.or()?;
                self.depth -= 1;
                if !self.eat_op(")") {
                    return Err("a `(` is not closed".into());
                }
                Ok(v)
            }
            Token::Word(w) if w == "true" => Ok(1.0),
            Token::Word(w) if w == "false" => Ok(0.0),
            // esmini's constants, which files written for it use (Vector's Euro NCAP
            // scenarios: `${65*pi/180}`); not the standard's.
            Token::Word(w) if w == "pi" => Ok(std::f64::consts::PI),
            Token::Word(w) if w == "e" => Ok(std::f64::consts::E),
            Token::Word(name) => self.call(&name),
            other => Err(format!("`{other}` where a value was expected")),
        }
    }

    fn call(&mut self, name: &str) -> Result<f64, String> {
        if !self.eat_op("(") {
            return Err(format!("`{name}` is neither a function nor true or false"));
        }
        self.deeper()?;
        let mut args = vec![self.or()?];
        while self.eat_op(",") {
            args.push(self.or()?);
        }
        self.depth -= 1;
        if !self.eat_op(")") {
            return Err(format!("`{name}(` is not closed"));
        }
        apply(name, &args)
    }
}

fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// The standard's function `name` of `args`.
fn apply(name: &str, args: &[f64]) -> Result<f64, String> {
    let one = |f: fn(f64) -> f64| -> Result<f64, String> {
        match args {
            [x] => finite(f(*x)).map_err(|_| format!("{name}({x}) is outside its domain")),
            _ => Err(format!("{name}() takes one argument, not {}", args.len())),
        }
    };
    let two = |f: fn(f64, f64) -> f64| -> Result<f64, String> {
        match args {
            [x, y] => {
                finite(f(*x, *y)).map_err(|_| format!("{name}({x}, {y}) is outside its domain"))
            }
            _ => Err(format!("{name}() takes two arguments, not {}", args.len())),
        }
    };
    match name {
        // The standard rounds half away from zero, as Rust's `round` does.
        "round" => one(f64::round),
        "floor" => one(f64::floor),
        "ceil" => one(f64::ceil),
        "sqrt" => one(f64::sqrt),
        "pow" => two(f64::powf),
        "sin" => one(f64::sin),
        "cos" => one(f64::cos),
        "tan" => one(f64::tan),
        "asin" => one(f64::asin),
        "acos" => one(f64::acos),
        "atan" => one(f64::atan),
        "abs" => one(f64::abs),
        "sign" => one(|x| {
            if x > 0.0 {
                1.0
            } else if x < 0.0 {
                -1.0
            } else {
                0.0
            }
        }),
        "max" => two(f64::max),
        "min" => two(f64::min),
        _ => Err(format!(
            "`{name}` is not a function of OpenSCENARIO's expressions"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(text: &str) -> Result<f64, String> {
        evaluate(text, &|name| match name {
            "Speed" => Ok(20.0),
            "Two" => Ok(2.0),
            _ => Err(format!("no parameter `{name}`")),
        })
    }

    #[test]
    fn the_standards_examples_evaluate_with_their_precedence() {
        assert_eq!(eval("$Speed / 3.6").unwrap(), 20.0 / 3.6);
        assert_eq!(eval("1 + 2 * 3").unwrap(), 7.0);
        assert_eq!(eval("(1 + 2) * 3").unwrap(), 9.0);
        assert_eq!(eval("-2 * -$Two").unwrap(), 4.0);
        assert_eq!(eval("7 % 4").unwrap(), 3.0);
        assert_eq!(eval("pow($Two, 10)").unwrap(), 1024.0);
        assert_eq!(
            eval("round(2.5) + floor(-0.5) + ceil(0.2)").unwrap(),
            3.0 - 1.0 + 1.0
        );
        assert_eq!(eval("max(1, min(5, 3))").unwrap(), 3.0);
        assert_eq!(eval("sign(-3) * abs(-4)").unwrap(), -4.0);
        assert_eq!(eval("1.5e1").unwrap(), 15.0);
        assert_eq!(eval("not true or 2 > 1 and $Speed == 20").unwrap(), 1.0);
        assert_eq!(eval("not (1 < 2)").unwrap(), 0.0);
        assert!((eval("asin(1) * 2").unwrap() - std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(
            eval("65 * pi / 180").unwrap(),
            65.0 * std::f64::consts::PI / 180.0
        );
        assert_eq!(eval("pow(e, 2)").unwrap(), std::f64::consts::E.powi(2));
    }

    #[test]
    fn what_cannot_be_evaluated_is_said() {
        for (text, says) in [
            ("1 / 0", "divides by zero"),
            ("1 % 0", "by zero"),
            ("sqrt(-1)", "outside its domain"),
            ("pow(10, 400)", "outside its domain"),
            ("$Nope + 1", "no parameter `Nope`"),
            ("(1 + 2", "not closed"),
            ("1 2", "after the expression's end"),
            ("frobnicate(1)", "not a function"),
            ("pow(1)", "two arguments"),
            ("1 +", "ends where a value was expected"),
            ("#", "not an operator"),
            ("$", "without a parameter's name"),
            ("speed", "neither a function"),
            ("pi(1)", "after the expression's end"),
        ] {
            let e = eval(text).unwrap_err();
            assert!(e.contains(says), "{text}: {e}");
        }
        let deep = "(".repeat(200) + "1" + &")".repeat(200);
        assert!(eval(&deep).unwrap_err().contains("nests deeper"));
        let negations = "-".repeat(100_000) + "1";
        assert!(eval(&negations).unwrap_err().contains("nests deeper"));
    }
}
