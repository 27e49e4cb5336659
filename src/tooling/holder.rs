//! ISO 5608 turning holders (`PCLNR 2525M12`), ISO 6261 boring bars (`S20S-SCLCR09`) and the
//! common threading holder codes (`SER 2525M16`, `SIR 0020P16`).

use super::insert::{self, Shape};

/// Clamping letters (ISO 5608 position 1).
pub const CLAMPINGS: &[(char, &str)] = &[
    ('C', "top clamp"),
    ('D', "rigid clamp"),
    ('M', "top clamp and pin"),
    ('N', "clamp into a notch"),
    ('P', "lever through the hole"),
    ('S', "screw through the hole"),
    ('W', "wedge"),
];

/// Tool styles (position 3): letter, cutting edge angle κr in degrees, whether the angle is
/// taken against a facing feed (toward the axis) rather than a turning feed (toward the chuck),
/// whether the shank is straight (no offset).
pub const STYLES: &[(char, f64, bool, bool)] = &[
    ('A', 90.0, false, true),
    ('B', 75.0, false, true),
    ('C', 90.0, true, true),
    ('D', 45.0, false, true),
    ('E', 60.0, false, true),
    ('F', 90.0, true, false),
    ('G', 90.0, false, false),
    ('H', 107.5, false, false),
    ('J', 93.0, false, false),
    ('K', 75.0, true, false),
    ('L', 95.0, false, false),
    ('M', 50.0, false, true),
    ('N', 63.0, false, true),
    ('P', 117.5, false, false),
    ('Q', 107.5, false, false),
    ('R', 75.0, false, false),
    ('S', 45.0, false, false),
    ('T', 60.0, false, false),
    ('U', 93.0, false, false),
    ('V', 72.5, false, true),
    ('W', 60.0, true, false),
    ('Y', 85.0, false, false),
];

/// Length letters (position 8 of ISO 5608, position 3 of ISO 6261), mm.
pub const LENGTHS: &[(char, f64)] = &[
    ('A', 32.0),
    ('B', 40.0),
    ('C', 50.0),
    ('D', 60.0),
    ('E', 70.0),
    ('F', 80.0),
    ('G', 90.0),
    ('H', 100.0),
    ('J', 110.0),
    ('K', 125.0),
    ('L', 140.0),
    ('M', 150.0),
    ('N', 160.0),
    ('P', 170.0),
    ('Q', 180.0),
    ('R', 200.0),
    ('S', 250.0),
    ('T', 300.0),
    ('U', 350.0),
    ('V', 400.0),
    ('W', 450.0),
    ('Y', 500.0),
];

/// Boring bar kinds (ISO 6261 position 1).
pub const BAR_KINDS: &[(char, &str)] = &[
    ('A', "steel, coolant through"),
    ('B', "steel, coolant through, damped"),
    ('C', "carbide"),
    ('D', "carbide, damped"),
    ('E', "carbide, coolant through"),
    ('F', "carbide, coolant through, damped"),
    ('H', "heavy metal"),
    ('S', "steel"),
];

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    pub letter: char,
    pub kappa: f64,
    pub facing: bool,
    pub straight: bool,
}

pub fn style(letter: char) -> Option<Style> {
    STYLES
        .iter()
        .find(|s| s.0 == letter)
        .map(|&(letter, kappa, facing, straight)| Style {
            letter,
            kappa,
            facing,
            straight,
        })
}

pub fn length(letter: char) -> Option<f64> {
    LENGTHS.iter().find(|l| l.0 == letter).map(|l| l.1)
}

/// How the holder is built.
#[derive(Clone, Debug, PartialEq)]
pub enum Body {
    /// A square or rectangular shank standing radially (along +x) on the turret.
    Shank { height: f64, width: f64, length: f64 },
    /// A round bar lying axially (along +z), for bores.
    Bar { kind: char, diameter: f64, length: f64 },
}

/// A holder for an ISO 1832 turning insert.
#[derive(Clone, Debug, PartialEq)]
pub struct Holder {
    pub clamping: char,
    pub shape: Shape,
    pub style: Style,
    pub clearance_letter: char,
    pub clearance: f64,
    /// R, L or N.
    pub hand: char,
    pub body: Body,
    /// Insert size code (cutting edge length, whole mm).
    pub size: u32,
    /// The inscribed circle of the insert it takes, mm.
    pub ic: f64,
}

/// A threading holder (`SER 2525M16`, `SIR 0020P16`).
#[derive(Clone, Debug, PartialEq)]
pub struct ThreadHolder {
    pub internal: bool,
    pub hand: char,
    pub body: Body,
    pub size: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum AnyHolder {
    Turning(Holder),
    Threading(ThreadHolder),
}

fn shown(c: Option<char>) -> String {
    match c {
        Some(c) if c.is_ascii_graphic() => format!("'{c}'"),
        Some(c) => format!("{c:?}"),
        None => "missing".into(),
    }
}

fn accepted<T>(set: &[(char, T)]) -> String {
    set.iter().map(|s| s.0.to_string()).collect::<Vec<_>>().join(" ")
}

/// Decode a holder or boring bar designation.
pub fn parse(code: &str) -> Result<AnyHolder, String> {
    if code.chars().count() > insert::MAX_CODE {
        return Err(format!(
            "is longer than {} characters: no designation is",
            insert::MAX_CODE
        ));
    }
    let s: Vec<char> = code.trim().to_ascii_uppercase().chars().filter(|c| *c != ' ').collect();
    if s.is_empty() {
        return Err("is empty".into());
    }
    // SER/SEL/SIR/SIL followed by digits (an ISO 5608 `SER…` has its clearance letter there).
    if s.len() >= 4 && s[0] == 'S' && matches!(s[1], 'E' | 'I') && matches!(s[2], 'R' | 'L') && s[3].is_ascii_digit() {
        return thread_holder(&s).map(AnyHolder::Threading);
    }
    if s.len() >= 2 && s[0].is_ascii_alphabetic() && s[1].is_ascii_digit() {
        return boring_bar(&s).map(AnyHolder::Turning);
    }
    external(&s).map(AnyHolder::Turning)
}

fn two_digits(s: &[char], i: usize, what: &str) -> Result<u32, String> {
    let t: String = s.iter().skip(i).take(2).collect();
    if t.len() == 2 && t.chars().all(|c| c.is_ascii_digit()) {
        Ok(t.parse().unwrap_or(0))
    } else {
        Err(format!("position {} ({what}) is {t:?}; expected two digits", i + 1))
    }
}

fn length_at(s: &[char], i: usize, default: f64) -> Result<f64, String> {
    match s.get(i) {
        Some('-') => Ok(default),
        Some(&c) => length(c).ok_or_else(|| {
            format!(
                "position {} (length) is {}; accepted: {} (or - for the preferred length)",
                i + 1,
                shown(Some(c)),
                accepted(LENGTHS)
            )
        }),
        None => Err(format!("ends before position {} (length letter)", i + 1)),
    }
}

/// Clamping, shape, style, clearance, hand, from `s[i..]`.
type Head = (char, Shape, Style, char, f64, char);

fn head(s: &[char], i: usize) -> Result<Head, String> {
    let at = |k: usize| s.get(i + k).copied();
    let clamping = at(0).filter(|c| CLAMPINGS.iter().any(|x| x.0 == *c)).ok_or_else(|| {
        format!(
            "position {} (clamping) is {}; accepted: {}",
            i + 1,
            shown(at(0)),
            accepted(CLAMPINGS)
        )
    })?;
    let shape = at(1).and_then(insert::shape).ok_or_else(|| {
        format!(
            "position {} (insert shape) is {}; accepted: {}",
            i + 2,
            shown(at(1)),
            insert::SHAPES
                .iter()
                .map(|s| s.0.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        )
    })?;
    let style = at(2).and_then(style).ok_or_else(|| {
        format!(
            "position {} (style) is {}; accepted: {}",
            i + 3,
            shown(at(2)),
            STYLES.iter().map(|s| s.0.to_string()).collect::<Vec<_>>().join(" ")
        )
    })?;
    let clearance_letter = at(3).filter(|c| insert::clearance(*c).is_some()).ok_or_else(|| {
        format!(
            "position {} (insert clearance) is {}; accepted: {}",
            i + 4,
            shown(at(3)),
            accepted(insert::CLEARANCES)
        )
    })?;
    let hand = at(4)
        .filter(|c| matches!(c, 'R' | 'L' | 'N'))
        .ok_or_else(|| format!("position {} (hand) is {}; accepted: R L N", i + 5, shown(at(4))))?;
    Ok((
        clamping,
        shape,
        style,
        clearance_letter,
        insert::clearance(clearance_letter).unwrap_or(0.0),
        hand,
    ))
}

/// The preferred length of a shank (ISO 5610 gives a length per height; these are its usual
/// values), for `-` in the length position.
pub fn preferred_length(height: f64) -> f64 {
    match height as u32 {
        0..=12 => 100.0,
        13..=16 => 100.0,
        17..=20 => 125.0,
        21..=25 => 150.0,
        26..=32 => 170.0,
        _ => 6.0 * height,
    }
}

fn size_of(s: &[char], i: usize, shape: Shape) -> Result<(u32, f64), String> {
    let size = two_digits(s, i, "insert size")?;
    if size == 0 {
        return Err(format!("position {} (insert size) is 00", i + 1));
    }
    Ok((size, insert::ic_from_size(shape, size)))
}

fn rest_ok(s: &[char], i: usize) -> Result<(), String> {
    // An optional special-tolerance letter, then an optional manufacturer's part after a dash.
    let mut k = i;
    if matches!(s.get(k), Some('Q' | 'F' | 'B')) {
        k += 1;
    }
    match s.get(k) {
        None | Some('-') => Ok(()),
        Some(&c) => Err(format!(
            "position {} is {}; after the insert size only a tolerance letter (Q F B) or a dash and a maker's suffix may follow",
            k + 1,
            shown(Some(c))
        )),
    }
}

fn external(s: &[char]) -> Result<Holder, String> {
    let (clamping, shape, style, clearance_letter, clearance, hand) = head(s, 0)?;
    let height = f64::from(two_digits(s, 5, "shank height")?);
    let width = f64::from(two_digits(s, 7, "shank width")?);
    if height == 0.0 || width == 0.0 {
        return Err("the shank's height and width must not be 00".into());
    }
    let length = length_at(s, 9, preferred_length(height))?;
    let (size, ic) = size_of(s, 10, shape)?;
    rest_ok(s, 12)?;
    Ok(Holder {
        clamping,
        shape,
        style,
        clearance_letter,
        clearance,
        hand,
        body: Body::Shank { height, width, length },
        size,
        ic,
    })
}

fn boring_bar(s: &[char]) -> Result<Holder, String> {
    let kind = s[0];
    if !BAR_KINDS.iter().any(|b| b.0 == kind) {
        return Err(format!(
            "position 1 (bar kind) is {}; accepted: {}",
            shown(Some(kind)),
            accepted(BAR_KINDS)
        ));
    }
    let diameter = f64::from(two_digits(s, 1, "bar diameter")?);
    if diameter == 0.0 {
        return Err("position 2 (bar diameter) is 00".into());
    }
    let length = length_at(s, 3, 10.0 * diameter)?;
    let mut i = 4;
    if s.get(i) == Some(&'-') {
        i += 1;
    }
    let (clamping, shape, style, clearance_letter, clearance, hand) = head(s, i)?;
    let (size, ic) = size_of(s, i + 5, shape)?;
    rest_ok(s, i + 7)?;
    Ok(Holder {
        clamping,
        shape,
        style,
        clearance_letter,
        clearance,
        hand,
        body: Body::Bar { kind, diameter, length },
        size,
        ic,
    })
}

fn thread_holder(s: &[char]) -> Result<ThreadHolder, String> {
    let internal = s[1] == 'I';
    let hand = s[2];
    let body = if internal {
        // SIR 0020P16: four digits, the last two the bar diameter.
        let d = f64::from(two_digits(s, 5, "bar diameter")?);
        if two_digits(s, 3, "bar diameter")? != 0 || d == 0.0 {
            return Err("positions 4–7 (bar diameter) must read 00dd, as in SIR 0020P16".into());
        }
        let length = length_at(s, 7, 10.0 * d)?;
        Body::Bar {
            kind: 'S',
            diameter: d,
            length,
        }
    } else {
        let height = f64::from(two_digits(s, 3, "shank height")?);
        let width = f64::from(two_digits(s, 5, "shank width")?);
        if height == 0.0 || width == 0.0 {
            return Err("the shank's height and width must not be 00".into());
        }
        let length = length_at(s, 7, preferred_length(height))?;
        Body::Shank { height, width, length }
    };
    let size = two_digits(s, 8, "insert size")?;
    if !insert::THREAD_SIZES.iter().any(|t| t.0 == size) {
        return Err(format!(
            "position 9 (threading insert size) is {size}; accepted: {}",
            insert::THREAD_SIZES
                .iter()
                .map(|t| t.0.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        ));
    }
    rest_ok(s, 10)?;
    Ok(ThreadHolder {
        internal,
        hand,
        body,
        size,
    })
}
