//! Tests of the G-code reader.

use super::*;
use proptest::prelude::*;

fn p(src: &str) -> Program<'_> {
    parse(src.as_bytes())
}

/// Everything read of a program, for comparing two readings: each block with its words and
/// assignments (not the ranges that locate them in their window), the expressions, the names,
/// the findings, the comments.
fn show(p: &Program) -> String {
    let blocks: Vec<String> = p.blocks().map(|b| show_block(&b)).collect();
    format!(
        "{blocks:#?} {:?} {:?} {:?} {:?}",
        p.exprs, p.names, p.errors, p.comments
    )
}

/// A block as [`show`] shows it.
fn show_block(b: &BlockRef) -> String {
    format!(
        "{} {:?} {:?} {} {} {} {:?} {:?} {:?} {:?} {:?}",
        b.line,
        b.span,
        b.n(),
        b.bad,
        b.percent,
        b.block_delete,
        b.oword(),
        b.message(),
        b.macro_stmt(),
        b.words(),
        b.assigns()
    )
}

/// Every word of the program, in order.
fn all_words(prog: &Program) -> Vec<Word> {
    prog.blocks().flat_map(|b| b.words().to_vec()).collect()
}

/// An expression as an S-expression, for comparing trees.
fn sx(prog: &Program, id: ExprId) -> String {
    match *prog.expr(id) {
        Expr::Num(x) => format!("{x}"),
        Expr::Param(param) => px(prog, param),
        Expr::Neg(a) => format!("(neg {})", sx(prog, a)),
        Expr::Not(a) => format!("(not {})", sx(prog, a)),
        Expr::Binary(op, a, b) => {
            let name = match op {
                BinOp::Pow => "**",
                BinOp::Mul => "*",
                BinOp::Div => "/",
                BinOp::Mod => "mod",
                BinOp::Add => "+",
                BinOp::Sub => "-",
                BinOp::Eq => "eq",
                BinOp::Ne => "ne",
                BinOp::Gt => "gt",
                BinOp::Ge => "ge",
                BinOp::Lt => "lt",
                BinOp::Le => "le",
                BinOp::And => "and",
                BinOp::Or => "or",
                BinOp::Xor => "xor",
            };
            format!("({name} {} {})", sx(prog, a), sx(prog, b))
        }
        Expr::Func(f, a) => format!("({} {})", format!("{f:?}").to_lowercase(), sx(prog, a)),
        Expr::Atan(y, x) => format!("(atan {} {})", sx(prog, y), sx(prog, x)),
        Expr::Exists(n) => format!("(exists {})", prog.name(n)),
    }
}

fn px(prog: &Program, param: Param) -> String {
    match param {
        Param::Numbered(n) => format!("#{n}"),
        Param::Named(n) => format!("#<{}>", prog.name(n)),
        Param::Indirect(e) => format!("#[{}]", sx(prog, e)),
    }
}

/// The words of the one block of `src`, as `X10.5` / `X=(expr)` strings; panics if `src` has errors.
fn words(src: &str) -> Vec<String> {
    let prog = p(src);
    assert!(prog.errors.is_empty(), "{src:?}: {:?}", prog.errors);
    assert_eq!(prog.len(), 1, "{src:?}");
    word_strings(&prog, &prog.block(0))
}

fn word_strings(prog: &Program, block: &BlockRef) -> Vec<String> {
    block
        .words()
        .iter()
        .map(|w| match w.value() {
            Value::Num(x) => format!("{}{x}", w.letter as char),
            Value::Expr(e) => format!("{}={}", w.letter as char, sx(prog, e)),
        })
        .collect()
}

/// The single syntax error of `src`: (line, col, message).
fn error(src: &[u8]) -> (u32, u32, String) {
    let prog = parse(src);
    assert_eq!(
        prog.errors.len(),
        1,
        "{:?}: {:?}",
        String::from_utf8_lossy(src),
        prog.errors
    );
    let e = &prog.errors[0];
    assert_eq!(e.kind, crate::finding::Kind::Syntax);
    (e.line, e.col, e.message.clone())
}

/// The expression of `#1=…` in `src`.
fn assigned(src: &str) -> String {
    let prog = p(src);
    assert!(prog.errors.is_empty(), "{src:?}: {:?}", prog.errors);
    sx(&prog, prog.block(0).assigns()[0].value)
}

fn text(src: &str, span: Span) -> &str {
    &src[span.range()]
}

// ---- words and numbers ----

#[test]
fn spaces_and_tabs_inside_words_and_numbers_are_ignored() {
    assert_eq!(words("X1 0.5"), ["X10.5"]);
    assert_eq!(words("G 0 1"), ["G1"]);
    assert_eq!(words("\tx\t1 . 5 z - 3"), ["X1.5", "Z-3"]);
    assert_eq!(words("G1X2Z3"), ["G1", "X2", "Z3"]);
}

#[test]
fn letters_are_case_insensitive() {
    assert_eq!(words("g1 x2 z-3 f.2"), ["G1", "X2", "Z-3", "F0.2"]);
}

#[test]
fn word_span_runs_from_letter_to_end_of_value() {
    let src = "G1  X 1 0.5  Z-3 ";
    let prog = p(src);
    let w = prog.block(0).words().to_vec();
    assert_eq!(text(src, w[0].span()), "G1");
    assert_eq!(text(src, w[1].span()), "X 1 0.5");
    assert_eq!(text(src, w[2].span()), "Z-3");
    let src = "X[1 + 2] y#<a b> ";
    let prog = p(src);
    let w = prog.block(0).words().to_vec();
    assert_eq!(text(src, w[0].span()), "X[1 + 2]");
    assert_eq!(text(src, w[1].span()), "y#<a b>");
}

#[test]
fn decimal_point_is_recorded() {
    let prog = p("X60 Z60. F.5 G1.5 S[1.5]");
    let w = prog.block(0).words().to_vec();
    let points: Vec<bool> = w.iter().map(|w| w.has_point).collect();
    assert_eq!(points, [false, true, true, true, false]);
}

#[test]
fn g1_5_is_a_plain_number_word() {
    assert_eq!(words("G1.5"), ["G1.5"]);
}

#[test]
fn numbers_are_exact() {
    assert_eq!(words("X0.1 Z-.3 F123456.789"), ["X0.1", "Z-0.3", "F123456.789"]);
    // Beyond the fast path: more digits than an f64 mantissa.
    let prog = p("X0.12345678901234567890123456789 Z12345678901234567890");
    let w = prog.block(0).words().to_vec();
    let want: f64 = "0.12345678901234567890123456789".parse().unwrap();
    assert_eq!(w[0].value(), Value::Num(want));
    assert_eq!(w[1].value(), Value::Num(12345678901234567890.0));
}

#[test]
fn double_sign_is_an_error() {
    let (line, col, msg) = error(b"G1 X--60");
    assert_eq!((line, col), (1, 6));
    assert!(msg.contains("after '-'") && msg.contains("found '-'"), "{msg}");
}

#[test]
fn point_alone_is_not_a_number() {
    let (_, col, msg) = error(b"G0 X.");
    assert_eq!(col, 5);
    assert!(msg.contains("no digits"), "{msg}");
    let (_, col, _) = error(b"X-. Z1");
    assert_eq!(col, 3);
}

#[test]
fn second_decimal_point_is_an_error_at_that_point() {
    let (_, col, msg) = error(b"X60.0.0");
    assert_eq!(col, 6);
    assert_eq!(msg, "number has two decimal points");
}

#[test]
fn e_is_a_word_not_an_exponent() {
    assert_eq!(words("X6e1"), ["X6", "E1"]);
}

#[test]
fn number_that_is_not_finite_is_an_error() {
    let src = format!("G1 X{}", "9".repeat(400));
    let (_, col, msg) = error(src.as_bytes());
    assert_eq!(col, 5);
    assert!(msg.contains("too large"), "{msg}");
    // 400 digits after the point are fine: the value is finite.
    let src = format!("X0.{}", "1".repeat(400));
    assert!(p(&src).errors.is_empty());
}

#[test]
fn letter_without_value_is_an_error() {
    let (_, col, msg) = error(b"G1 X");
    assert_eq!(col, 5);
    assert_eq!(msg, "expected a value after X, found end of line");
    let (_, col, msg) = error(b"G1 X Z1");
    assert_eq!(col, 6);
    assert_eq!(msg, "expected a value after X, found 'Z'");
    let (_, _, msg) = error(b"X;1");
    assert!(msg.contains("found ';'"), "{msg}");
}

#[test]
fn repeated_and_unknown_letters_are_left_to_the_interpreter() {
    assert_eq!(words("G1 G1 X1 X2 Q1 Y3"), ["G1", "G1", "X1", "X2", "Q1", "Y3"]);
}

#[test]
fn stray_characters_are_errors() {
    let (_, col, msg) = error(b"G1 (c) 12");
    assert_eq!(col, 8);
    assert!(msg.contains("found '1'"), "{msg}");
    let (_, col, msg) = error(b"G1 = 2");
    assert_eq!(col, 4);
    assert!(msg.contains("found '='"), "{msg}");
    let (_, _, msg) = error(b"G1 \x1a");
    assert!(msg.contains("control byte 0x1A"), "{msg}");
    let (_, col, msg) = error(b"G1 X1)");
    assert_eq!(col, 6);
    assert_eq!(msg, "')' outside a comment");
}

// ---- comments ----

#[test]
fn comments_are_skipped_and_kept() {
    let src = "G1 (first) X2 (second)";
    let prog = p(src);
    assert_eq!(word_strings(&prog, &prog.block(0)), ["G1", "X2"]);
    let texts: Vec<&str> = prog.comments.iter().map(|c| text(src, c.text)).collect();
    assert_eq!(texts, ["first", "second"]);
    assert_eq!(prog.comments[0].line, 1);
}

#[test]
fn comments_do_not_nest() {
    // The first ')' closes: " c)" is outside the comment.
    let (_, col, msg) = error(b"(a (b) c)");
    assert_eq!(col, 9);
    assert!(msg.contains("found ')'") && msg.contains("do not nest"), "{msg}");
    let (_, col, msg) = error(b"G1 (a (b)) X1");
    assert_eq!(col, 10);
    assert!(msg.contains("do not nest"), "{msg}");
}

#[test]
fn unclosed_comment_is_an_error_at_its_paren() {
    let prog = p("G1 X1 (no end\nG0 X2");
    assert_eq!(prog.errors.len(), 1);
    assert_eq!((prog.errors[0].line, prog.errors[0].col), (1, 7));
    assert!(prog.errors[0].message.contains("unclosed comment"));
    // What was read is kept; the next line is read normally.
    assert!(prog.block(0).bad);
    assert_eq!(word_strings(&prog, &prog.block(0)), ["G1", "X1"]);
    assert!(!prog.block(1).bad);
    assert_eq!(word_strings(&prog, &prog.block(1)), ["G0", "X2"]);
}

#[test]
fn semicolon_hides_the_rest_of_the_line() {
    assert_eq!(words("G1 ; X10"), ["G1"]);
    assert_eq!(words("G1 X1;Z2 (x"), ["G1", "X1"]);
    // Inside ( ) a ';' is just text.
    assert_eq!(words("G1 (a;b) X2"), ["G1", "X2"]);
}

#[test]
fn comment_only_lines_produce_no_block() {
    let prog = p("(header)\n   \n; note\n\t(a) (b) ;c\nG1\n");
    assert!(prog.errors.is_empty());
    assert_eq!(prog.len(), 1);
    assert_eq!(prog.block(0).line, 5);
}

#[test]
fn msg_print_debug_comments_give_the_message_text() {
    let src = "(MSG,Hello world)\nG1 (print, x=#1)\n( Debug , v)\n(msghello)\n(MSG , )";
    let prog = p(src);
    assert!(prog.errors.is_empty());
    let msgs: Vec<(u32, Option<&str>)> = prog
        .blocks()
        .map(|b| (b.line, b.message().map(|m| text(src, m))))
        .collect();
    assert_eq!(
        msgs,
        [
            (1, Some("Hello world")),
            (2, Some(" x=#1")),
            (3, Some(" v")),
            (5, Some(" "))
        ]
    );
}

// ---- bytes, BOM, line ends ----

#[test]
fn bytes_above_ascii_are_allowed_only_in_comments() {
    for b in 0x80u8..=0xFF {
        let mut src = b"G1 (".to_vec();
        src.push(b);
        src.extend_from_slice(b") X1 ;");
        src.push(b);
        let prog = parse(&src);
        assert!(prog.errors.is_empty(), "byte {b:#x} in a comment");
        assert_eq!(word_strings(&prog, &prog.block(0)), ["G1", "X1"]);

        let mut src = b"G1 X1 ".to_vec();
        src.push(b);
        let (_, col, msg) = error(&src);
        assert_eq!(col, 7);
        assert!(msg.starts_with(&format!("byte 0x{b:02X} outside a comment")), "{msg}");
    }
}

#[test]
fn columns_count_characters_not_bytes() {
    // "(é)" is 3 characters, 4 bytes: X is at column 5, the bad '.' value at column 6.
    let (_, col, _) = error("(é) X.".as_bytes());
    assert_eq!(col, 6);
    // A byte outside a comment inside a value.
    let (_, col, msg) = error("(ö)G1 X1é".as_bytes());
    assert_eq!(col, 9);
    assert!(msg.contains("0xC3"), "{msg}");
}

#[test]
fn utf8_bom_is_skipped() {
    let src = "\u{FEFF}G1 X1\nX.";
    let prog = p(src);
    assert_eq!(word_strings(&prog, &prog.block(0)), ["G1", "X1"]);
    assert_eq!(prog.block(0).span, Span::new(3, 8));
    assert_eq!(prog.block(0).words()[0].span(), Span::new(3, 5));
    let (line, col, _) = error("\u{FEFF}G1 X.".as_bytes());
    assert_eq!((line, col), (1, 5));
    // A BOM anywhere else is a byte outside a comment.
    let (line, col, _) = error("G1\n\u{FEFF}G1".as_bytes());
    assert_eq!((line, col), (2, 1));
}

#[test]
fn crlf_and_lone_cr_end_lines() {
    let src = "G1 X1\r\nG2 X2\rG3 X3\n\rG4 (c)\r\n";
    let prog = p(src);
    assert!(prog.errors.is_empty());
    let lines: Vec<u32> = prog.blocks().map(|b| b.line).collect();
    assert_eq!(lines, [1, 2, 3, 5]);
    let spans: Vec<&str> = prog.blocks().map(|b| text(src, b.span)).collect();
    assert_eq!(spans, ["G1 X1", "G2 X2", "G3 X3", "G4 (c)"]);
    assert_eq!(prog.line_count(), 5);
    let (line, col, _) = error(b"G1\r\rG1\r\nX.\r");
    assert_eq!((line, col), (4, 2));
}

#[test]
fn a_one_megabyte_line_reads_fast() {
    let mut src = String::with_capacity(1 << 20);
    while src.len() < (1 << 20) {
        src.push_str("G1 X1.5 Z-2 ");
    }
    src.push_str("X.");
    let t = std::time::Instant::now();
    let prog = p(&src);
    assert!(t.elapsed().as_secs_f64() < 5.0, "{:?}", t.elapsed());
    assert_eq!(prog.errors.len(), 1);
    assert_eq!(prog.errors[0].col as usize, src.len());
    assert_eq!(
        prog.blocks().map(|b| b.words().len()).sum::<usize>(),
        (src.len() - 2) / 12 * 3
    );
    // One number a megabyte long (no point): not finite.
    let src = format!("X{}", "1".repeat(1 << 20));
    assert!(error(src.as_bytes()).2.contains("too large"));
    // A megabyte comment.
    let src = format!("G1 ({}) X1", "c".repeat(1 << 20));
    assert_eq!(words(&src), ["G1", "X1"]);
}

// ---- %, /, N ----

#[test]
fn a_block_is_40_bytes() {
    // A program holds one block per line: its size is most of the reader's memory.
    assert_eq!(std::mem::size_of::<super::Block>(), 40);
}

#[test]
fn percent_line_and_percent_with_program_number() {
    let prog = p("%\n%O1200(TOKARKA)\n % \n");
    assert!(prog.errors.is_empty());
    assert_eq!(prog.len(), 3);
    assert!(prog.blocks().all(|b| b.percent));
    assert_eq!(prog.block(0).oword(), None);
    let b1 = prog.block(1);
    let o = b1.oword().unwrap();
    assert_eq!((o.name, &o.op), (OName::Number(1200), &OOp::ProgramNumber));
    let (_, col, msg) = error(b"G1 %");
    assert_eq!(col, 4);
    assert!(msg.contains("first character"), "{msg}");
}

#[test]
fn slash_first_is_block_delete() {
    let prog = p("/G1 X1\n / N10 G0\n");
    assert!(prog.errors.is_empty());
    assert!(prog.block(0).block_delete && prog.block(1).block_delete);
    assert_eq!(prog.block(1).n(), Some(10));
    assert!(!p("G1").block(0).block_delete);
    let (_, col, msg) = error(b"G1 /X1");
    assert_eq!(col, 4);
    assert!(msg.contains("block delete"), "{msg}");
}

#[test]
fn n_number_at_block_start() {
    let prog = p("N10 G1\nN 2 0X1\nn0005\nN01G50S0600");
    assert!(prog.errors.is_empty());
    let ns: Vec<Option<u64>> = prog.blocks().map(|b| b.n()).collect();
    assert_eq!(ns, [Some(10), Some(20), Some(5), Some(1)]);
    assert_eq!(word_strings(&prog, &prog.block(3)), ["G50", "S600"]);
    assert_eq!(p(&format!("N{}", u64::MAX)).block(0).n(), Some(u64::MAX));
}

#[test]
fn bad_n_numbers_are_errors() {
    let (_, col, msg) = error(b"N1.5 G1");
    assert_eq!(col, 3);
    assert!(msg.contains("whole number"), "{msg}");
    let (_, col, msg) = error(b"N99999999999999999999 G1");
    assert_eq!(col, 1);
    assert!(msg.contains("too large"), "{msg}");
    let (_, col, msg) = error(b"G1 N10");
    assert_eq!(col, 4);
    assert!(msg.contains("start of the block"), "{msg}");
    let (_, col, _) = error(b"N10 N20");
    assert_eq!(col, 5);
    let (_, col, _) = error(b"N-1");
    assert_eq!(col, 2);
    let (_, col, _) = error(b"N");
    assert_eq!(col, 2);
}

#[test]
fn findings_carry_the_block_n_number() {
    let prog = p("N5 X.");
    assert_eq!(prog.errors[0].n, Some(5));
}

// ---- O-words ----

fn oword(src: &str) -> (Program<'_>, OWord) {
    let prog = p(src);
    assert!(prog.errors.is_empty(), "{src:?}: {:?}", prog.errors);
    let o = prog.block(0).oword().cloned().expect("an o-word");
    (prog, o)
}

#[test]
fn named_oword_forms() {
    let (prog, o) = oword("o<My Sub> sub");
    assert_eq!(o.op, OOp::Sub);
    let OName::Named(id) = o.name else { panic!() };
    assert_eq!(prog.name(id), "mysub");
    for (src, op) in [
        ("O<x> endsub", OOp::EndSub(None)),
        ("o<x> do", OOp::Do),
        ("o<x> endwhile", OOp::EndWhile),
        ("o<x> else", OOp::Else),
        ("o<x> endif", OOp::EndIf),
        ("o<x> break", OOp::Break),
        ("o<x> continue", OOp::Continue),
        ("o<x> endrepeat", OOp::EndRepeat),
        ("o<x> return", OOp::Return(None)),
        ("o<x> call", OOp::Call(vec![])),
        ("o<x> END SUB", OOp::EndSub(None)),
    ] {
        assert_eq!(oword(src).1.op, op, "{src}");
    }
}

#[test]
fn oword_conditions_and_arguments() {
    let (prog, o) = oword("o100 while [#1 LT 10]");
    assert_eq!(o.name, OName::Number(100));
    let OOp::While(c) = o.op else { panic!() };
    assert_eq!(sx(&prog, c), "(lt #1 10)");
    let (prog, o) = oword("o<a> if[#<x> gt 0]");
    let OOp::If(c) = o.op else { panic!() };
    assert_eq!(sx(&prog, c), "(gt #<x> 0)");
    let (prog, o) = oword("o<a> elseif [1]");
    let OOp::ElseIf(c) = o.op else { panic!() };
    assert_eq!(sx(&prog, c), "1");
    let (prog, o) = oword("o<a> repeat [5]");
    let OOp::Repeat(c) = o.op else { panic!() };
    assert_eq!(sx(&prog, c), "5");
    let (prog, o) = oword("o<a> endsub [#1 * 2]");
    let OOp::EndSub(Some(c)) = o.op else { panic!() };
    assert_eq!(sx(&prog, c), "(* #1 2)");
    let (prog, o) = oword("o<a> return [3]");
    let OOp::Return(Some(c)) = o.op else { panic!() };
    assert_eq!(sx(&prog, c), "3");
    let src = "o<turning> call [1] [2.5] [#<x>] [-1] (comment)";
    let (prog, o) = oword(src);
    let OOp::Call(args) = &o.op else { panic!() };
    let args: Vec<String> = args.iter().map(|&a| sx(&prog, a)).collect();
    assert_eq!(args, ["1", "2.5", "#<x>", "-1"]);
    assert_eq!(text(src, o.span), "o<turning> call [1] [2.5] [#<x>] [-1]");
}

#[test]
fn oword_names_are_interned_once() {
    let prog = p("o<A b> sub\n#<a B> = 1\nO<ab> endsub");
    assert!(prog.errors.is_empty());
    assert_eq!(prog.names, ["ab"]);
}

#[test]
fn fanuc_program_numbers() {
    for (src, n) in [
        ("O1234", 1234),
        ("O0358 ( FANUC 0T )", 358),
        (":0100( FLANGE OP.2 )", 100),
        ("o1", 1),
    ] {
        let (_, o) = oword(src);
        assert_eq!((o.name, o.op), (OName::Number(n), OOp::ProgramNumber), "{src}");
    }
    let (_, o) = oword("N5 O0002 (x)");
    assert_eq!(o.name, OName::Number(2));
    let (_, o) = oword("O1 call");
    assert_eq!((o.name, o.op), (OName::Number(1), OOp::Call(vec![])));
}

#[test]
fn bad_owords_are_errors() {
    let (_, col, msg) = error(b"o<x>");
    assert_eq!(col, 5);
    assert!(msg.contains("sub, endsub, call"), "{msg}");
    let (_, col, msg) = error(b"o1 foo");
    assert_eq!(col, 4);
    assert!(msg.contains("unknown O-word keyword 'foo'"), "{msg}");
    let (_, col, msg) = error(b"o1 while #1");
    assert_eq!(col, 10);
    assert!(msg.contains("'[' after WHILE"), "{msg}");
    let (_, col, msg) = error(b"O1234 G0 X1");
    assert_eq!(col, 7);
    assert!(msg.contains("stands alone") && msg.contains("found 'G'"), "{msg}");
    let (_, col, msg) = error(b"O1234 (x) G0 X1");
    assert_eq!(col, 11);
    assert!(msg.contains("after an O-word"), "{msg}");
    let (_, col, msg) = error(b"G0 O1");
    assert_eq!(col, 4);
    assert!(msg.contains("first word"), "{msg}");
    let (_, col, _) = error(b"o<ab");
    assert_eq!(col, 2);
    let (_, col, _) = error(b"o<> sub");
    assert_eq!(col, 2);
    let (_, col, _) = error(b"O");
    assert_eq!(col, 2);
    let (_, _, msg) = error(b"O99999999999");
    assert!(msg.contains("too large"), "{msg}");
    let (_, col, msg) = error(b"o1 call 1");
    assert_eq!(col, 9);
    assert!(msg.contains("after an O-word"), "{msg}");
    let (_, _, msg) = error(b"o1 endrepeatx");
    assert!(msg.contains("endrepeatx"), "{msg}");
    let (_, col, _) = error(b":x");
    assert_eq!(col, 2);
}

// ---- expressions ----

#[test]
fn expression_precedence_follows_rs274ngc() {
    assert_eq!(assigned("#1=[1+2*3]"), "(+ 1 (* 2 3))");
    assert_eq!(assigned("#1=[1*2+3]"), "(+ (* 1 2) 3)");
    assert_eq!(assigned("#1=[2**3*2]"), "(* (** 2 3) 2)");
    assert_eq!(assigned("#1=[1+2 lt 3*4]"), "(lt (+ 1 2) (* 3 4))");
    assert_eq!(assigned("#1=[1 eq 2 and 3 ne 4]"), "(and (eq 1 2) (ne 3 4))");
    assert_eq!(assigned("#1=[1 or 2 xor 3 and 4]"), "(and (xor (or 1 2) 3) 4)");
    assert_eq!(assigned("#1=[7 mod 4 / 2]"), "(/ (mod 7 4) 2)");
    assert_eq!(assigned("#1=[1 ge 2 le 3 gt 4]"), "(gt (le (ge 1 2) 3) 4)");
}

#[test]
fn binary_operators_are_left_associative() {
    assert_eq!(assigned("#1=[1-2-3]"), "(- (- 1 2) 3)");
    assert_eq!(assigned("#1=[8/4/2]"), "(/ (/ 8 4) 2)");
    assert_eq!(assigned("#1=[2**3**2]"), "(** (** 2 3) 2)");
}

#[test]
fn unary_signs_and_blanks_in_expressions() {
    assert_eq!(assigned("#1=[-#2]"), "(neg #2)");
    assert_eq!(assigned("#1=[2*-3]"), "(* 2 -3)");
    assert_eq!(assigned("#1=[+[1]]"), "1");
    assert_eq!(assigned("#1=[ 1 * * 2 ]"), "(** 1 2)");
    assert_eq!(assigned("#1=[1 A N D 2]"), "(and 1 2)");
    assert_eq!(assigned("#1=[1 ltabs[2]]"), "(lt 1 (abs 2))");
    assert_eq!(assigned("#1=-[1]"), "(neg 1)");
}

#[test]
fn functions() {
    assert_eq!(assigned("#1=ABS[-1]"), "(abs -1)");
    assert_eq!(
        assigned("#1=[acos[1]+asin[1]+cos[1]+exp[1]+fix[1]+fup[1]+round[1]+ln[1]+sin[1]+sqrt[1]+tan[1]]"),
        "(+ (+ (+ (+ (+ (+ (+ (+ (+ (+ (acos 1) (asin 1)) (cos 1)) (exp 1)) (fix 1)) (fup 1)) (round 1)) (ln 1)) (sin 1)) (sqrt 1)) (tan 1))"
    );
    assert_eq!(assigned("#1=ATAN[1]/[#2]"), "(atan 1 #2)");
    assert_eq!(assigned("#1=[atan[1]/[2]/3]"), "(/ (atan 1 2) 3)");
    assert_eq!(assigned("#1=EXISTS[#<_Foo>]"), "(exists _foo)");
    assert_eq!(words("X sin[0] Z-cos[0]"), ["X=(sin 0)", "Z=(neg (cos 0))"]);
}

#[test]
fn bad_functions_are_errors() {
    let (_, col, msg) = error(b"#1=ATAN[1]");
    assert_eq!(col, 11);
    assert!(msg.contains("ATAN[y]/[x]"), "{msg}");
    let (_, col, msg) = error(b"#1=[1+foo[2]]");
    assert_eq!(col, 7);
    assert!(msg.contains("unknown function 'FOO'"), "{msg}");
    let (_, col, msg) = error(b"#1=ABS 2");
    assert_eq!(col, 8);
    assert!(msg.contains("'[' after ABS"), "{msg}");
    let (_, col, msg) = error(b"#1=EXISTS[#1]");
    assert_eq!(col, 12);
    assert!(msg.contains("EXISTS[#<name>]"), "{msg}");
}

#[test]
fn bad_expressions_are_errors() {
    let (_, col, msg) = error(b"G1 X[1+2");
    assert_eq!(col, 5);
    assert!(msg.contains("unclosed '['"), "{msg}");
    // Blanks are ignored inside brackets too: this is 12.
    assert_eq!(words("X[1 2 ]"), ["X=12"]);
    let (_, col, msg) = error(b"G1 X[1 #2]");
    assert_eq!(col, 8);
    assert_eq!(msg, "expected an operator or ']', found '#'");
    let (_, col, msg) = error(b"X[1 +]");
    assert_eq!(col, 6);
    assert!(msg.contains("found ']'"), "{msg}");
    let (_, col, _) = error(b"X[]");
    assert_eq!(col, 3);
    let (_, col, msg) = error(b"X[1 ? 2]");
    assert_eq!(col, 5);
    assert!(msg.contains("found '?'"), "{msg}");
}

#[test]
fn nesting_is_capped() {
    let ok = format!(
        "X{}1{}",
        "[".repeat(MAX_NESTING as usize),
        "]".repeat(MAX_NESTING as usize)
    );
    assert!(p(&ok).errors.is_empty());
    let deep = format!(
        "X{}1{}",
        "[".repeat(MAX_NESTING as usize + 1),
        "]".repeat(MAX_NESTING as usize + 1)
    );
    let (_, col, msg) = error(deep.as_bytes());
    assert_eq!(col, MAX_NESTING + 2);
    assert!(msg.contains("nested deeper"), "{msg}");
    // Indirection counts too, and a very deep input does not overflow the stack.
    let hashes = format!("X{}1", "#".repeat(100_000));
    assert!(error(hashes.as_bytes()).2.contains("nested deeper"));
    let brackets = format!("X{}", "abs[".repeat(100_000));
    assert!(error(brackets.as_bytes()).2.contains("nested deeper"));
}

#[test]
fn nesting_at_the_cap_through_every_precedence_level_fits_the_stack() {
    // Each bracket level opens every precedence level: the deepest recursion the reader allows.
    let levels = MAX_NESTING as usize;
    let unit = "[1 or 1 eq 1 + 1 * 1 ** ";
    let src = format!("X{}1{}", unit.repeat(levels), "]".repeat(levels));
    // Unoptimised, this takes between 256 KiB and 512 KiB of stack; threads get 2 MiB by default.
    let errors = std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || p(&src).errors)
        .unwrap()
        .join()
        .unwrap();
    assert!(errors.is_empty(), "{errors:?}");
}

// ---- parameters and assignments ----

#[test]
fn parameter_references_in_words() {
    assert_eq!(
        words("X#1 Z-#<_z> F##2 S#[1+2] G#<mode>"),
        ["X=#1", "Z=(neg #<_z>)", "F=#[#2]", "S=#[(+ 1 2)]", "G=#<mode>"]
    );
    assert_eq!(words("X#1 2"), ["X=#12"]);
    assert_eq!(words("X#1.0"), ["X=#1"]);
}

#[test]
fn assignments_anywhere_in_the_line() {
    let src = "#1=2 G1 X#1 #<Z Start>=[#1+1] #[3]=-4 ##5=#6";
    let prog = p(src);
    assert!(prog.errors.is_empty(), "{:?}", prog.errors);
    let b = &prog.block(0);
    assert_eq!(word_strings(&prog, b), ["G1", "X=#1"]);
    let a: Vec<String> = b
        .assigns()
        .iter()
        .map(|a| format!("{}={}", px(&prog, a.target), sx(&prog, a.value)))
        .collect();
    assert_eq!(a, ["#1=2", "#<zstart>=(+ #1 1)", "#[3]=-4", "#[#5]=#6"]);
    let spans: Vec<&str> = b.assigns().iter().map(|a| text(src, a.span)).collect();
    assert_eq!(spans, ["#1=2", "#<Z Start>=[#1+1]", "#[3]=-4", "##5=#6"]);
    // Fanuc macro variables with a trailing comment.
    assert_eq!(assigned("#501=350.(FLANGE DIA.)"), "350");
}

#[test]
fn bad_assignments_are_errors() {
    let (_, col, msg) = error(b"G1 #1");
    assert_eq!(col, 6);
    assert!(msg.contains("'=' after the parameter"), "{msg}");
    let (_, col, msg) = error(b"#1.5=2");
    assert_eq!(col, 2);
    assert!(msg.contains("whole number"), "{msg}");
    let (_, col, _) = error(b"#1=");
    assert_eq!(col, 4);
    let (_, col, _) = error(b"#=1");
    assert_eq!(col, 2);
    // The column and the message name the byte found, not the blanks before it.
    let (_, col, msg) = error(b"G1 #  \t =1");
    assert_eq!(col, 9);
    assert!(msg.ends_with("found '='"), "{msg}");
    let (_, col, _) = error(b"#1=2+3");
    assert_eq!(col, 5);
    let (_, _, msg) = error(b"#99999999999=1");
    assert!(msg.contains("whole number"), "{msg}");
}

// ---- lines, blocks, errors ----

#[test]
fn one_error_per_line_and_the_rest_of_the_line_is_skipped() {
    let prog = p("G1 X1 Y. Z3 X..\nG0 X2\nX--1 Y.");
    let found: Vec<(u32, u32)> = prog.errors.iter().map(|e| (e.line, e.col)).collect();
    assert_eq!(found, [(1, 8), (3, 3)]);
    assert_eq!(word_strings(&prog, &prog.block(0)), ["G1", "X1"]);
    assert!(prog.block(0).bad && !prog.block(1).bad && prog.block(2).bad);
    assert!(word_strings(&prog, &prog.block(2)).is_empty());
}

#[test]
fn block_span_and_line_are_physical() {
    let src = "\n\nG1 X1 (c)\n\n  G0\n";
    let prog = p(src);
    let got: Vec<(u32, &str)> = prog.blocks().map(|b| (b.line, text(src, b.span))).collect();
    assert_eq!(got, [(3, "G1 X1 (c)"), (5, "  G0")]);
}

#[test]
fn empty_input_reads_to_nothing() {
    let prog = parse(b"");
    assert!(prog.is_empty() && prog.errors.is_empty());
}

#[test]
fn corpus_like_linuxcnc_program_reads_cleanly() {
    let src = "%\n\
        o<g76base> sub\n\
        #<toolno> =  #1 (= 10)\n\
        o<if1> if [#<_lathe_diameter_mode> EQ 1]\n\
          #<xi> = [#<xi> / 2]\n\
        o<if1> endif\n\
        T#<toolno> M6 G43\n\
        G#<mode> X#<xi> Z[#<zi> + #<p>] F[ABS[#<p>]]\n\
        G76 P[#<p>] Z#<z> I#<i> J#<j> K#<k> R#<r> Q#<q> H#<h> E#<e> L#<l>\n\
        (debug, done)\n\
        o<g76base> endsub\n\
        %\n";
    let prog = p(src);
    assert!(prog.errors.is_empty(), "{:?}", prog.errors);
    assert_eq!(prog.len(), 12);
}

// ---- properties ----

fn check_invariants(src: &[u8]) {
    check_invariants_of(src, parse(src));
    check_invariants_of(src, super::parse_fanuc(src));
    for per_window in [1, 2, 5] {
        assert_windows_read_as_whole(src, per_window);
    }
}

/// Read in windows of `per_window` blocks, the program is the whole reading: walked in order,
/// and block by block in an order that jumps back and forth across windows (each jump past the
/// cache reads a window again), both dialects.
fn assert_windows_read_as_whole(src: &[u8], per_window: usize) {
    for macro_b in [false, true] {
        let whole = lexer::parse_with(src, true, macro_b, usize::MAX);
        let windowed = lexer::parse_with(src, true, macro_b, per_window);
        assert_eq!(whole.len(), windowed.len());
        assert_eq!(show(&whole), show(&windowed), "{per_window} blocks a window");
        let n = windowed.len();
        // Last, first, second last, second, …: every access to a window not held reads it again.
        let order = (0..n).map(|k| if k % 2 == 0 { n - 1 - k / 2 } else { k / 2 });
        for i in order {
            let (a, b) = (whole.block(i), windowed.block(i));
            assert_eq!(b.index(), i);
            assert_eq!(show_block(&a), show_block(&b));
        }
        for line in 0..=whole.line_count() + 1 {
            let at = |p: &Program| p.block_at_line(line).map(|b| b.index());
            assert_eq!(at(&whole), at(&windowed), "line {line}");
        }
        let rare = |p: &Program| p.rare_blocks().map(|b| b.index()).collect::<Vec<_>>();
        assert_eq!(rare(&whole), rare(&windowed));
        assert_eq!(
            rare(&whole),
            whole
                .blocks()
                .filter(|b| b.rare.is_some())
                .map(|b| b.index())
                .collect::<Vec<_>>()
        );
    }
}

#[test]
fn a_program_read_in_windows_is_the_program_read_whole() {
    // Every program and fixture of the repository, one block a window and a few.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    let mut stack = vec![
        root.join("programs"),
        root.join("tests/cases"),
        root.join("tests/fixtures"),
    ];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if matches!(path.extension().and_then(|e| e.to_str()), Some("nc" | "ngc")) {
                let src = std::fs::read(&path).unwrap();
                if src.len() > 200_000 {
                    continue;
                }
                for per_window in [1, 3, 64] {
                    assert_windows_read_as_whole(&src, per_window);
                }
                n += 1;
            }
        }
    }
    assert!(n > 250, "{n} programs");
}

#[test]
fn a_window_read_again_is_counted_and_a_small_program_is_read_once() {
    let src = "G0 X1\n#1=2\nG1 X#1 Z[#1+1]\no<a> sub\no<a> endsub\n".repeat(3000);
    let whole = parse(src.as_bytes());
    assert_eq!(whole.len(), 15_000);
    // Four windows of 4096 blocks: all held since the first reading.
    for i in (0..whole.len()).rev() {
        whole.block(i);
    }
    whole.blocks().count();
    assert_eq!(whole.windows_reread(), 0);
    // One block a window: the cache holds 8 of 15,000.
    let w = lexer::parse_with(src.as_bytes(), true, false, 1);
    assert_eq!(w.windows_reread(), 0);
    w.block(0);
    assert_eq!(w.windows_reread(), 0);
    w.block(14_999);
    assert_eq!(w.windows_reread(), 1);
    w.block(14_999);
    assert_eq!(w.windows_reread(), 1);
    // A flow that jumps round the windows, more of them than the cache holds, over and over:
    // past twice the number of windows read again, every window stays.
    let round = lexer::parse_with(src.as_bytes(), true, false, 100);
    let windows = 150;
    // Walks of the whole program read the windows not held, and do not count toward that.
    for _ in 0..3 {
        assert_eq!(round.blocks().count(), 15_000);
    }
    let walked = round.windows_reread();
    assert_eq!(walked, 3 * (windows as u64 - 8));
    for _ in 0..50 {
        for k in 0..windows {
            round.block(k * 100);
        }
    }
    let reread = round.windows_reread() - walked;
    assert!(
        (2 * windows as u64..=3 * windows as u64 + 16).contains(&reread),
        "{reread}"
    );
    // The walk over the rare blocks reads only the windows that hold one.
    assert_eq!(w.rare_blocks().count(), 9000);
    assert!(w.windows_reread() <= 1 + 9000);
}

fn check_invariants_of(src: &[u8], prog: Program) {
    let lines = prog.line_count();
    for e in &prog.errors {
        assert!(e.line >= 1 && e.line <= lines, "finding line {} of {lines}", e.line);
        assert!(e.col >= 1);
    }
    let mut last = 0;
    for b in prog.blocks() {
        assert!(b.line > last && b.line <= lines);
        last = b.line;
        assert!(b.span.start <= b.span.end && b.span.end as usize <= src.len());
        for w in b.words() {
            assert!(w.letter.is_ascii_uppercase());
            assert!(b.span.start <= w.span().start && w.span().start < w.span().end);
            assert!(w.span().end <= b.span.end);
            if let Value::Num(x) = w.value() {
                assert!(x.is_finite());
            }
        }
        for a in b.assigns() {
            assert!(b.span.start <= a.span.start && a.span.end <= b.span.end);
            assert!((a.value as usize) < prog.exprs.len());
        }
    }
    // One finding per line at most, and each names a line with a bad block.
    let bad: Vec<u32> = prog.blocks().filter(|b| b.bad).map(|b| b.line).collect();
    let err: Vec<u32> = prog.errors.iter().map(|e| e.line).collect();
    assert_eq!(bad, err);
    // Expressions only point backwards (the arena is a DAG built bottom-up).
    for (i, e) in prog.exprs.iter().enumerate() {
        let kids: Vec<ExprId> = match *e {
            Expr::Neg(a) | Expr::Not(a) | Expr::Func(_, a) => vec![a],
            Expr::Binary(_, a, b) | Expr::Atan(a, b) => vec![a, b],
            Expr::Param(Param::Indirect(a)) => vec![a],
            _ => vec![],
        };
        assert!(kids.iter().all(|&k| (k as usize) < i));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn arbitrary_bytes_never_panic(src in proptest::collection::vec(any::<u8>(), 0..400)) {
        check_invariants(&src);
    }

    #[test]
    fn gcode_like_text_never_panics(
        src in "([GXZNOIKFSTMgxzno#\\[\\]()<>;%/:=. 0-9+*\\-\t\r\n]|abs|atan|exists|while|call|sub|endsub|if|and|mod|\\*\\*|é){0,120}"
    ) {
        check_invariants(src.as_bytes());
    }

    #[test]
    fn blanks_anywhere_in_words_do_not_change_them(
        ws in proptest::collection::vec(("[ABCDFGHIJKLMPQRSTUVWXYZ]", -99999i64..99999, 0u32..1000, any::<bool>()), 1..8),
        blanks in proptest::collection::vec(0usize..3, 64),
    ) {
        let mut plain = String::new();
        for (l, i, f, point) in &ws {
            plain.push_str(l);
            plain.push_str(&i.to_string());
            if *point {
                plain.push('.');
                plain.push_str(&format!("{f:03}"));
            }
        }
        let mut spaced = String::new();
        for (k, ch) in plain.chars().enumerate() {
            spaced.push_str(&" \t"[..blanks[k % blanks.len()].min(2)]);
            spaced.push(ch);
        }
        let a = p(&plain);
        let b = p(&spaced);
        prop_assert!(a.errors.is_empty() && b.errors.is_empty());
        let wa: Vec<(u8, Value, bool)> = all_words(&a).iter().map(|w| (w.letter, w.value(), w.has_point)).collect();
        let wb: Vec<(u8, Value, bool)> = all_words(&b).iter().map(|w| (w.letter, w.value(), w.has_point)).collect();
        prop_assert_eq!(&wa, &wb);
        for (w, (l, i, f, point)) in wa.iter().zip(&ws) {
            prop_assert_eq!(w.0, l.as_bytes()[0]);
            let want: f64 = if *point { format!("{i}.{f:03}").parse().unwrap() } else { *i as f64 };
            prop_assert_eq!(w.1, Value::Num(want));
        }
    }

    #[test]
    fn the_fast_line_reader_reads_as_the_general_reader(
        lines in proptest::collection::vec(
            "(([GXZUWFSTIKRgxz]|N|n|O|E|e)(-|\\+)?[0-9]{0,17}(\\.[0-9]{0,4})?(\\.)?[ \t]{0,2}|[0-9 .(;#\\[-]){0,9}",
            1..12,
        ),
        crlf in any::<bool>(),
    ) {
        let src = lines.join(if crlf { "\r\n" } else { "\n" });
        for macro_b in [false, true] {
            let fast = lexer::parse_with(src.as_bytes(), true, macro_b, WINDOW_BLOCKS);
            let general = lexer::parse_with(src.as_bytes(), false, macro_b, WINDOW_BLOCKS);
            prop_assert_eq!(show(&fast), show(&general));
        }
    }

    #[test]
    fn the_fast_line_reader_declines_macro_statements_as_the_general_reader_reads_them(
        lines in proptest::collection::vec(
            "(N[0-9]{1,3} ?)?(GOTO ?[0-9#]{1,3}|IF ?\\[#1 ?(EQ|GT) ?[0-9]\\] ?(GOTO[0-9]{1,2}|THEN ?#2=[0-9])|WHILE ?\\[#1 ?LT ?3\\] ?DO[0-4]|END[0-4]|DO[1-3]|G65 ?P9[0-9]{3} ?A1\\.|[GXZ][0-9]{1,3})",
            1..12,
        ),
    ) {
        let src = lines.join("\n");
        let fast = lexer::parse_with(src.as_bytes(), true, true, WINDOW_BLOCKS);
        let general = lexer::parse_with(src.as_bytes(), false, true, WINDOW_BLOCKS);
        prop_assert_eq!(show(&fast), show(&general));
    }

    #[test]
    fn random_macro_text_never_panics(
        src in "([GXZNOIKFSTMgxzno#\\[\\]()<>;%/:=,. 0-9+*\\-\t\r\n]|IF|GOTO|THEN|WHILE|DO|END|EQ|NE|GT|LE|AND|OR|XOR|MOD|BIN|BCD|POW|ATAN|ROUND|FIX|FUP|SQRT|G65|G66|G67|M98|M99|é){0,120}"
    ) {
        check_invariants(src.as_bytes());
    }
}

#[test]
fn macro_b_statements_are_read_only_by_the_fanuc_reader() {
    use super::{parse_fanuc, MacroOp};
    let src =
        b"N5 IF [#1 EQ 2] GOTO 10\nIF[#1GT0]THEN#2=3\nWHILE [#1 LT 3] DO1\nDO2\nEND2\nEND1\nGOTO #3\n#1 = #2 + 1\n";
    let lcnc = parse(src);
    // LinuxCNC: every one of these lines is a syntax error, as before.
    assert_eq!(lcnc.errors.len(), 8, "{:?}", lcnc.errors);
    let f = parse_fanuc(src);
    assert!(f.errors.is_empty(), "{:?}", f.errors);
    let ops: Vec<MacroOp> = f.blocks().filter_map(|b| b.macro_stmt().map(|m| m.op)).collect();
    assert!(matches!(ops[0], MacroOp::IfGoto(..)));
    assert!(matches!(ops[1], MacroOp::IfThen(_)));
    assert!(matches!(ops[2], MacroOp::Do(Some(_), 1)));
    assert!(matches!(ops[3], MacroOp::Do(None, 2)));
    assert_eq!(&ops[4..6], &[MacroOp::End(2), MacroOp::End(1)]);
    assert!(matches!(ops[6], MacroOp::Goto(_)));
    assert_eq!(f.block(0).n(), Some(5));
    assert_eq!(f.block(1).assigns().len(), 1);
    assert_eq!(f.block(7).assigns().len(), 1);
}

#[test]
fn bad_macro_statements_are_syntax_findings_with_their_column() {
    let cases: [(&[u8], u32, &str); 6] = [
        (b"WHILE [1] DO4", 13, "loop number must be 1, 2 or 3"),
        (b"WHILE [1]", 10, "DO1, DO2 or DO3"),
        (b"IF [1] X1", 8, "GOTO or THEN"),
        (b"IF [1] THEN G0", 13, "an assignment"),
        (b"GOTO 10 X5", 9, "nothing but comments after a macro statement"),
        (b"END", 4, "1, 2 or 3 after END"),
    ];
    for (src, col, msg) in cases {
        let p = super::parse_fanuc(src);
        assert_eq!(p.errors.len(), 1, "{}", String::from_utf8_lossy(src));
        assert_eq!(
            p.errors[0].col,
            col,
            "{}: {}",
            String::from_utf8_lossy(src),
            p.errors[0].message
        );
        assert!(p.errors[0].message.contains(msg), "{}", p.errors[0].message);
    }
}

#[test]
fn fanuc_priorities_put_and_with_times_and_or_with_plus() {
    // 2 + 12 AND 10 is 2 + (12 AND 10) on Fanuc; rs274ngc reads [2 + 12] AND 10.
    let f = super::parse_fanuc(b"#1 = [2 + 12 AND 10]");
    let l = parse(b"#1 = [2 + 12 AND 10]");
    let top = |p: &Program| p.exprs[p.block(0).assigns()[0].value as usize];
    assert!(matches!(top(&f), Expr::Binary(BinOp::Add, ..)));
    assert!(matches!(top(&l), Expr::Binary(BinOp::And, ..)));
}
#[test]
fn lines_past_the_cache_are_counted_as_the_reader_reads_them() {
    // Past the windows the first reading keeps, a plain line is counted without being read
    // (`shape.rs`): blank lines, blanks only, an N alone, bad lines and lines the general reader
    // reads must leave the windows where a reading of every line puts them.
    let tail = "\n \t\nN5\nG1 X1 Z-2.5\n(note)\nX--1\nG1 X1 0.5\n#1=2\nG1 X#1\nn7 g0 x.5\n\nO12\nG1 X.\n  \n";
    let src = format!("{}{}", "G0 X1\n".repeat(10), tail.repeat(4));
    for per_window in [1, 2, 3] {
        assert_windows_read_as_whole(src.as_bytes(), per_window);
    }
}
