//! The memory budget's linker script read: the regions of its `MEMORY` blocks, with the
//! rules the firmware's linker (LLD) reads them by. One parser for the firmware's build
//! script (a real board's `memory.x` takes the budget's LENGTHs) and for `camsim
//! firmware-check` (an image's flash and RAM against the budget), so a budget that links
//! is the budget that is checked.
//!
//! What it reads:
//! - `/* ... */` and `//` comments are skipped everywhere (a `MEMORY` block inside a
//!   comment is not read); a `/*` never closed is an error;
//! - `MEMORY { NAME [(attributes)] : ORIGIN = n, LENGTH = n ... }`, the keys also as LLD
//!   spells them (`org`, `o`; `len`, `l`), in either order;
//! - a number: decimal, decimal with a `K`/`k` (× 1024) or `M`/`m` (× 1024²) suffix, or
//!   `0x`/`0X` hex (no suffix, as LLD);
//! - every sum and product checked: a value past 64 bits (`17592186044417M`) is an
//!   error, never a wrap.
//!
//! An expression (`128K - 4`, `ORIGIN(FLASH) + 4K`) is refused with its region and key:
//! the budget is plain numbers. No allocation: the errors borrow the script's text.

use core::fmt;

/// One region of a `MEMORY` block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region<'a> {
    /// The region's name (`FLASH`).
    pub name: &'a str,
    /// Its ORIGIN, bytes.
    pub origin: u64,
    /// Its LENGTH, bytes.
    pub length: u64,
    /// Its LENGTH as written (`128K`, `0x8000`).
    pub length_text: &'a str,
    /// The script's line (from 1) of its name.
    pub line: usize,
}

/// Why a linker script's region cannot be read. Each names the line where it has one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryMapError<'a> {
    /// A `/*` comment with no `*/`.
    UnclosedComment {
        /// Line of the `/*`.
        line: usize,
    },
    /// A `"` with no closing `"`.
    UnclosedQuote {
        /// Line of the `"`.
        line: usize,
    },
    /// No `MEMORY { ... }` outside comments.
    NoMemoryBlock,
    /// A `MEMORY {` never closed by `}`.
    UnclosedBlock {
        /// Line of the `MEMORY`.
        line: usize,
    },
    /// A token where the syntax wants another.
    Unexpected {
        /// Its line.
        line: usize,
        /// The token (empty: the end of the script).
        found: &'a str,
        /// What the syntax wants there.
        expected: &'static str,
    },
    /// The region is not in any `MEMORY` block.
    NoRegion {
        /// The region looked for.
        region: &'a str,
    },
    /// The region is defined twice.
    DuplicateRegion {
        /// The region.
        region: &'a str,
        /// Line of its first definition.
        first: usize,
        /// Line of its second.
        line: usize,
    },
    /// A region without ORIGIN or without LENGTH, or with one of them twice.
    Key {
        /// The region.
        region: &'a str,
        /// `ORIGIN` or `LENGTH`.
        key: &'static str,
        /// Line of the region's name.
        line: usize,
        /// `true`: given twice; `false`: missing.
        twice: bool,
    },
    /// A value that is not a number by the rules above.
    NotANumber {
        /// The region.
        region: &'a str,
        /// `ORIGIN` or `LENGTH`.
        key: &'static str,
        /// The value as written.
        text: &'a str,
        /// Its line.
        line: usize,
    },
    /// A value past 2⁶⁴ − 1 bytes.
    Overflow {
        /// The region.
        region: &'a str,
        /// `ORIGIN` or `LENGTH`.
        key: &'static str,
        /// The value as written.
        text: &'a str,
        /// Its line.
        line: usize,
    },
    /// A value followed by an operator: an expression, not a number.
    Expression {
        /// The region.
        region: &'a str,
        /// `ORIGIN` or `LENGTH`.
        key: &'static str,
        /// The value's first token.
        text: &'a str,
        /// The operator after it.
        operator: &'a str,
        /// Its line.
        line: usize,
    },
}

/// The rule a value must follow, as the errors state it.
const NUMBER_RULE: &str =
    "a number is decimal, decimal with a K or M suffix (x 1024, x 1024^2), or 0x hex";

/// At most this many characters of a token are quoted in an error.
const QUOTE_CHARS: usize = 40;

/// A token quoted in an error, cut after [`QUOTE_CHARS`] characters.
struct Quoted<'a>(&'a str);

impl fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return f.write_str("the end of the script");
        }
        f.write_str("`")?;
        for c in self.0.chars().take(QUOTE_CHARS) {
            fmt::Write::write_char(f, c)?;
        }
        if self.0.chars().nth(QUOTE_CHARS).is_some() {
            f.write_str("…")?;
        }
        f.write_str("`")
    }
}

impl fmt::Display for MemoryMapError<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use MemoryMapError as E;
        match *self {
            E::UnclosedComment { line } => write!(f, "line {line}: a /* comment is never closed by */"),
            E::UnclosedQuote { line } => write!(f, "line {line}: a \" is never closed"),
            E::NoMemoryBlock => f.write_str("no MEMORY { ... } block outside comments"),
            E::UnclosedBlock { line } => write!(f, "line {line}: the MEMORY block is never closed by }}"),
            E::Unexpected { line, found, expected } => {
                write!(f, "line {line}: {} where the MEMORY block needs {expected}", Quoted(found))
            }
            E::NoRegion { region } => write!(
                f,
                "no region {region} in its MEMORY block (a `{region} : ORIGIN = ..., LENGTH = ...` line)"
            ),
            E::DuplicateRegion { region, first, line } => {
                write!(f, "line {line}: region {region} is defined twice (first on line {first})")
            }
            E::Key { region, key, line, twice: true } => {
                write!(f, "line {line}: region {region} gives {key} twice")
            }
            E::Key { region, key, line, twice: false } => {
                write!(f, "line {line}: region {region} has no {key} = ...")
            }
            E::NotANumber { region, key, text, line } => write!(
                f,
                "line {line}: {key} of {region} is {}: not a number ({NUMBER_RULE})",
                Quoted(text)
            ),
            E::Overflow { region, key, text, line } => write!(
                f,
                "line {line}: {key} of {region} is {}: more than 2^64 - 1 bytes (a length must fit 64 bits)",
                Quoted(text)
            ),
            E::Expression { region, key, text, operator, line } => write!(
                f,
                "line {line}: {key} of {region} is an expression ({} then {}): the budget is read as one number ({NUMBER_RULE})",
                Quoted(text),
                Quoted(operator)
            ),
        }
    }
}

/// Region `name` of the script's `MEMORY` blocks, or why not (a syntax error anywhere
/// in a `MEMORY` block, a bad value of any region, the region missing or defined twice).
pub fn region<'a>(script: &'a str, name: &'a str) -> Result<Region<'a>, MemoryMapError<'a>> {
    let mut found: Option<Region<'a>> = None;
    for r in regions(script) {
        let r = r?;
        if r.name != name {
            continue;
        }
        if let Some(first) = found {
            return Err(MemoryMapError::DuplicateRegion {
                region: r.name,
                first: first.line,
                line: r.line,
            });
        }
        found = Some(r);
    }
    found.ok_or(MemoryMapError::NoRegion { region: name })
}

/// Every region of the script's `MEMORY` blocks in order; an error ends the walk. A
/// script without a `MEMORY` block yields [`MemoryMapError::NoMemoryBlock`].
pub fn regions(script: &str) -> Regions<'_> {
    Regions {
        lex: Lexer {
            script,
            pos: 0,
            peeked: None,
        },
        block_line: None,
        blocks: 0,
        done: false,
    }
}

/// The walk of [`regions`].
pub struct Regions<'a> {
    lex: Lexer<'a>,
    /// Line of the `MEMORY` whose block the walk is in.
    block_line: Option<usize>,
    /// `MEMORY` blocks entered.
    blocks: usize,
    done: bool,
}

impl<'a> Iterator for Regions<'a> {
    type Item = Result<Region<'a>, MemoryMapError<'a>>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let item = self.step();
        if !matches!(item, Some(Ok(_))) {
            self.done = true;
        }
        item
    }
}

impl<'a> Regions<'a> {
    /// The next region, an error, or `None` at the end.
    fn step(&mut self) -> Option<Result<Region<'a>, MemoryMapError<'a>>> {
        loop {
            let Some(open) = self.block_line else {
                match self.enter_block() {
                    Ok(true) => continue,
                    Ok(false) if self.blocks == 0 => {
                        return Some(Err(MemoryMapError::NoMemoryBlock))
                    }
                    Ok(false) => return None,
                    Err(e) => return Some(Err(e)),
                }
            };
            let token = match self.lex.next() {
                Ok(Some(t)) => t,
                Ok(None) => return Some(Err(MemoryMapError::UnclosedBlock { line: open })),
                Err(e) => return Some(Err(e)),
            };
            if token.text == "}" {
                self.block_line = None;
                continue;
            }
            return Some(entry(&mut self.lex, token));
        }
    }

    /// Skips to the next `MEMORY {` and enters it; `false` at the end of the script.
    fn enter_block(&mut self) -> Result<bool, MemoryMapError<'a>> {
        while let Some(t) = self.lex.next()? {
            if t.text != "MEMORY" {
                continue;
            }
            let line = self.lex.line(t.at);
            expect(&mut self.lex, "{", "`{` after MEMORY")?;
            self.block_line = Some(line);
            self.blocks = self.blocks.saturating_add(1);
            return Ok(true);
        }
        Ok(false)
    }
}

/// The keys of an entry: ORIGIN and LENGTH, with LLD's other spellings.
fn key_of(text: &str) -> Option<&'static str> {
    match text {
        "ORIGIN" | "org" | "o" => Some("ORIGIN"),
        "LENGTH" | "len" | "l" => Some("LENGTH"),
        _ => None,
    }
}

/// One entry, its name already read: `[(attributes)] : key = n [,] key = n`.
fn entry<'a>(lex: &mut Lexer<'a>, name: Token<'a>) -> Result<Region<'a>, MemoryMapError<'a>> {
    let line = lex.line(name.at);
    if is_punct(name.text) {
        return Err(MemoryMapError::Unexpected {
            line,
            found: name.text,
            expected: "a region name or `}`",
        });
    }
    let mut t = lex.require("`:` after the region's name")?;
    if t.text == "(" {
        while t.text != ")" {
            t = lex.require("`)` closing the region's attributes")?;
        }
        t = lex.require("`:` after the region's attributes")?;
    }
    if t.text != ":" {
        return Err(lex.unexpected(t, "`:` after the region's name"));
    }
    let (mut origin, mut length): (Option<u64>, Option<(u64, &'a str)>) = (None, None);
    for i in 0..2 {
        let mut k = lex.require("ORIGIN = ... or LENGTH = ...")?;
        if i == 1 && k.text == "," {
            k = lex.require("ORIGIN = ... or LENGTH = ... after `,`")?;
        }
        let key =
            key_of(k.text).ok_or_else(|| lex.unexpected(k, "ORIGIN = ... or LENGTH = ..."))?;
        expect(lex, "=", "`=` after the key")?;
        let v = lex.require("a number after `=`")?;
        let value = number(lex, name.text, key, v)?;
        let twice = match key {
            "ORIGIN" => origin.replace(value).is_some(),
            _ => length.replace((value, v.text)).is_some(),
        };
        if twice {
            return Err(MemoryMapError::Key {
                region: name.text,
                key,
                line,
                twice: true,
            });
        }
    }
    let missing = |key| MemoryMapError::Key {
        region: name.text,
        key,
        line,
        twice: false,
    };
    let origin = origin.ok_or_else(|| missing("ORIGIN"))?;
    let (length, length_text) = length.ok_or_else(|| missing("LENGTH"))?;
    Ok(Region {
        name: name.text,
        origin,
        length,
        length_text,
        line,
    })
}

/// The value token `v` of `key` in `region` as bytes; the token after it must not be an
/// operator (an expression).
fn number<'a>(
    lex: &mut Lexer<'a>,
    region: &'a str,
    key: &'static str,
    v: Token<'a>,
) -> Result<u64, MemoryMapError<'a>> {
    let line = lex.line(v.at);
    if let Some(next) = lex.peek()? {
        let op = next.text.starts_with([
            '+', '-', '*', '/', '&', '|', '<', '>', '~', '!', '?', '%', '(',
        ]) || (v.text.starts_with(|c: char| c.is_ascii_alphabetic()) && next.text == "(");
        if op {
            return Err(MemoryMapError::Expression {
                region,
                key,
                text: v.text,
                operator: next.text,
                line,
            });
        }
    }
    match parse_number(v.text) {
        Ok(n) => Ok(n),
        Err(NumberError::NotANumber) => Err(MemoryMapError::NotANumber {
            region,
            key,
            text: v.text,
            line,
        }),
        Err(NumberError::Overflow) => Err(MemoryMapError::Overflow {
            region,
            key,
            text: v.text,
            line,
        }),
    }
}

/// Why a number token is not a number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumberError {
    /// Not of the form (see the module's rules).
    NotANumber,
    /// Past 2⁶⁴ − 1.
    Overflow,
}

/// A linker-script number in bytes: decimal, decimal with a `K`/`k` or `M`/`m` suffix,
/// or `0x`/`0X` hex; checked, never wrapped.
pub fn parse_number(text: &str) -> Result<u64, NumberError> {
    let (digits, radix, scale) =
        if let Some(hex) = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
            (hex, 16, 1)
        } else if let Some(d) = text.strip_suffix(['K', 'k']) {
            (d, 10, 1024)
        } else if let Some(d) = text.strip_suffix(['M', 'm']) {
            (d, 10, 1024 * 1024)
        } else {
            (text, 10, 1)
        };
    if digits.is_empty() {
        return Err(NumberError::NotANumber);
    }
    let mut n: u64 = 0;
    for c in digits.chars() {
        let d = c.to_digit(radix).ok_or(NumberError::NotANumber)?;
        n = n
            .checked_mul(u64::from(radix))
            .and_then(|n| n.checked_add(u64::from(d)))
            .ok_or(NumberError::Overflow)?;
    }
    n.checked_mul(scale).ok_or(NumberError::Overflow)
}

/// Reads the next token and checks it is `want`.
fn expect<'a>(
    lex: &mut Lexer<'a>,
    want: &str,
    expected: &'static str,
) -> Result<(), MemoryMapError<'a>> {
    let t = lex.require(expected)?;
    if t.text == want {
        Ok(())
    } else {
        Err(lex.unexpected(t, expected))
    }
}

/// The one-character tokens.
const PUNCT: [u8; 8] = [b'{', b'}', b'(', b')', b':', b',', b'=', b';'];

fn is_punct(text: &str) -> bool {
    matches!(text.as_bytes(), [b] if PUNCT.contains(b))
}

/// A token: its text and its byte offset in the script.
#[derive(Clone, Copy, Debug)]
struct Token<'a> {
    text: &'a str,
    at: usize,
}

/// The script cut into tokens: punctuation, quoted strings and words, with comments and
/// white space skipped.
struct Lexer<'a> {
    script: &'a str,
    pos: usize,
    peeked: Option<Option<Token<'a>>>,
}

impl<'a> Lexer<'a> {
    /// Line (from 1) of byte offset `at`.
    fn line(&self, at: usize) -> usize {
        let before = self.script.as_bytes().get(..at).unwrap_or_default();
        before
            .iter()
            .filter(|b| **b == b'\n')
            .count()
            .saturating_add(1)
    }

    fn unexpected(&self, t: Token<'a>, expected: &'static str) -> MemoryMapError<'a> {
        MemoryMapError::Unexpected {
            line: self.line(t.at),
            found: t.text,
            expected,
        }
    }

    /// The next token, which must exist.
    fn require(&mut self, expected: &'static str) -> Result<Token<'a>, MemoryMapError<'a>> {
        self.next()?.ok_or(MemoryMapError::Unexpected {
            line: self.line(self.script.len()),
            found: "",
            expected,
        })
    }

    fn peek(&mut self) -> Result<Option<Token<'a>>, MemoryMapError<'a>> {
        if let Some(t) = self.peeked {
            return Ok(t);
        }
        let t = self.lex()?;
        self.peeked = Some(t);
        Ok(t)
    }

    fn next(&mut self) -> Result<Option<Token<'a>>, MemoryMapError<'a>> {
        match self.peeked.take() {
            Some(t) => Ok(t),
            None => self.lex(),
        }
    }

    fn at(&self, i: usize) -> Option<u8> {
        self.script.as_bytes().get(i).copied()
    }

    fn starts(&self, i: usize, s: &str) -> bool {
        self.script
            .as_bytes()
            .get(i..)
            .is_some_and(|b| b.starts_with(s.as_bytes()))
    }

    /// Offset of the first `s` at or after `from`.
    fn find(&self, from: usize, s: &str) -> Option<usize> {
        let rest = self.script.get(from..)?;
        rest.find(s).map(|i| from.saturating_add(i))
    }

    /// Skips white space and comments.
    fn skip(&mut self) -> Result<(), MemoryMapError<'a>> {
        let end = self.script.len();
        while let Some(b) = self.at(self.pos) {
            if b.is_ascii_whitespace() {
                self.pos = self.pos.saturating_add(1);
            } else if self.starts(self.pos, "/*") {
                let close = self.find(self.pos.saturating_add(2), "*/");
                let close = close.ok_or(MemoryMapError::UnclosedComment {
                    line: self.line(self.pos),
                })?;
                self.pos = close.saturating_add(2);
            } else if self.starts(self.pos, "//") {
                self.pos = self.find(self.pos, "\n").unwrap_or(end);
            } else {
                break;
            }
        }
        Ok(())
    }

    fn lex(&mut self) -> Result<Option<Token<'a>>, MemoryMapError<'a>> {
        self.skip()?;
        let start = self.pos;
        let Some(b) = self.at(start) else {
            return Ok(None);
        };
        let end = if PUNCT.contains(&b) {
            start.saturating_add(1)
        } else if b == b'"' {
            let close = self.find(start.saturating_add(1), "\"");
            close
                .ok_or(MemoryMapError::UnclosedQuote {
                    line: self.line(start),
                })?
                .saturating_add(1)
        } else {
            let mut i = start;
            while let Some(c) = self.at(i) {
                let stop = c.is_ascii_whitespace()
                    || PUNCT.contains(&c)
                    || c == b'"'
                    || self.starts(i, "/*")
                    || self.starts(i, "//");
                if stop {
                    break;
                }
                i = i.saturating_add(1);
            }
            i
        };
        self.pos = end;
        // Tokens end at ASCII bytes or at the end, so on character boundaries.
        Ok(self
            .script
            .get(start..end)
            .map(|text| Token { text, at: start }))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    const BUDGET: &str = "/* budget\n * MEMORY { FLASH : ORIGIN = 0, LENGTH = 1K } */\nMEMORY\n{\n  FLASH : ORIGIN = 0x00000000, LENGTH = 128K\n  RAM   : ORIGIN = 0x20000000, LENGTH = 16K\n}\n";

    fn length<'a>(script: &'a str, name: &'a str) -> Result<u64, MemoryMapError<'a>> {
        region(script, name).map(|r| r.length)
    }

    #[test]
    fn numbers_decimal_suffixed_and_hex() {
        assert_eq!(parse_number("32768"), Ok(32768));
        assert_eq!(parse_number("128K"), Ok(131_072));
        assert_eq!(parse_number("128k"), Ok(131_072));
        assert_eq!(parse_number("2M"), Ok(2_097_152));
        assert_eq!(parse_number("2m"), Ok(2_097_152));
        assert_eq!(parse_number("0x8000"), Ok(32768));
        assert_eq!(parse_number("0XfF"), Ok(255));
        // LLD reads 010 as decimal ten, not octal.
        assert_eq!(parse_number("010"), Ok(10));
        for bad in [
            "", "K", "0x", "12Q", "+5", "-1", "1.5K", "0x20K", "1KK", "1 K",
        ] {
            assert_eq!(parse_number(bad), Err(NumberError::NotANumber), "{bad}");
        }
        // 2^44 + 1 MiB = 2^64 + 2^20: a wrap would give 1 MiB.
        assert_eq!(parse_number("17592186044417M"), Err(NumberError::Overflow));
        assert_eq!(parse_number("18446744073709551615"), Ok(u64::MAX));
        assert_eq!(
            parse_number("18446744073709551616"),
            Err(NumberError::Overflow)
        );
        assert_eq!(
            parse_number("0x10000000000000000"),
            Err(NumberError::Overflow)
        );
        // 2^54 K = 2^64.
        assert_eq!(
            parse_number("18014398509481984K"),
            Err(NumberError::Overflow)
        );
        assert_eq!(parse_number("18014398509481983K"), Ok(u64::MAX - 1023));
    }

    #[test]
    fn the_block_outside_comments_is_read() {
        assert_eq!(length(BUDGET, "FLASH"), Ok(128 * 1024));
        assert_eq!(length(BUDGET, "RAM"), Ok(16 * 1024));
        let r = region(BUDGET, "RAM").unwrap();
        assert_eq!((r.origin, r.length_text, r.line), (0x2000_0000, "16K", 6));
        // Line comments, attributes, LLD's short keys, no spaces, one line, hex lengths.
        let s = "// MEMORY { RAM : ORIGIN = 0, LENGTH = 1 }\nMEMORY{FLASH(rx):org=0,len=0x8000 RAM (rwx) : o = 536870912 , l = 4k // tail\n}";
        assert_eq!(length(s, "FLASH"), Ok(0x8000));
        assert_eq!(length(s, "RAM"), Ok(4096));
        // A block only in a comment is no block; other commands around it are skipped.
        assert_eq!(
            length("/* MEMORY { RAM : ORIGIN = 0, LENGTH = 1K } */", "RAM"),
            Err(MemoryMapError::NoMemoryBlock)
        );
        let s = "ENTRY(Reset);\nSECTIONS { .text : { *(.text*) } > FLASH } /* x */\nMEMORY { RAM : ORIGIN = 0, LENGTH = 2K }";
        assert_eq!(length(s, "RAM"), Ok(2048));
    }

    #[test]
    fn refusals_name_the_region_the_text_and_the_rule() {
        let over = "MEMORY {\n FLASH : ORIGIN = 0, LENGTH = 17592186044417M\n}";
        let e = region(over, "FLASH").unwrap_err();
        assert_eq!(
            e,
            MemoryMapError::Overflow {
                region: "FLASH",
                key: "LENGTH",
                text: "17592186044417M",
                line: 2
            }
        );
        let msg = std::format!("{e}");
        assert!(
            msg.contains("line 2")
                && msg.contains("LENGTH of FLASH")
                && msg.contains("17592186044417M")
                && msg.contains("64 bits"),
            "{msg}"
        );
        let e = std::format!(
            "{}",
            region("MEMORY { RAM : ORIGIN = 0, LENGTH = 12Q }", "RAM").unwrap_err()
        );
        assert!(
            e.contains("LENGTH of RAM is `12Q`: not a number") && e.contains("0x hex"),
            "{e}"
        );
        assert_eq!(
            region(BUDGET, "CCM"),
            Err(MemoryMapError::NoRegion { region: "CCM" })
        );
        assert!(std::format!("{}", region(BUDGET, "CCM").unwrap_err()).contains("no region CCM"));
        let twice = "MEMORY { RAM : ORIGIN = 0, LENGTH = 1K\n RAM : ORIGIN = 0, LENGTH = 2K }";
        assert_eq!(
            length(twice, "RAM"),
            Err(MemoryMapError::DuplicateRegion {
                region: "RAM",
                first: 1,
                line: 2
            })
        );
        let expr = "MEMORY { RAM : ORIGIN = 0, LENGTH = 128K - 4 }";
        assert!(matches!(
            length(expr, "RAM"),
            Err(MemoryMapError::Expression { operator: "-", .. })
        ));
        let call = "MEMORY { RAM : ORIGIN = 0, LENGTH = LENGTH(FLASH) }";
        assert!(matches!(
            length(call, "RAM"),
            Err(MemoryMapError::Expression { .. })
        ));
        assert!(matches!(
            length("MEMORY { RAM : ORIGIN = 0 }", "RAM"),
            Err(MemoryMapError::Unexpected { .. })
        ));
        assert!(matches!(
            length("MEMORY { RAM : ORIGIN = 0, ORIGIN = 1 }", "RAM"),
            Err(MemoryMapError::Key { twice: true, .. })
        ));
        assert!(matches!(
            length("MEMORY { RAM : ORIGIN = 0, LENGTH = 1K ", "RAM"),
            Err(MemoryMapError::UnclosedBlock { line: 1 })
        ));
        assert!(matches!(
            length("MEMORY { RAM : ORIGIN = 0, LENGTH = 1K } /* open", "RAM"),
            Err(MemoryMapError::UnclosedComment { line: 1 })
        ));
        // A bad value in another region is refused too (the linker refuses it).
        let other = "MEMORY { FLASH : ORIGIN = 0, LENGTH = 1Q\n RAM : ORIGIN = 0, LENGTH = 1K }";
        assert!(matches!(
            length(other, "RAM"),
            Err(MemoryMapError::NotANumber {
                region: "FLASH",
                ..
            })
        ));
    }

    #[test]
    fn a_huge_token_is_quoted_cut() {
        let long = "9".repeat(10_000);
        let script = std::format!("MEMORY {{ RAM : ORIGIN = 0, LENGTH = {long}Q }}");
        let e = std::format!("{}", region(&script, "RAM").unwrap_err());
        assert!(e.len() < 300 && e.contains('…'), "{e}");
    }
}
