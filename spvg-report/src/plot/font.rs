//! The built-in pixel font of the plots: 5x7 glyphs on a baseline with two descender rows
//! (9 rows a cell), drawn at integer scales. Glyphs are kept as text "sheets" (`#` set,
//! `.` clear, one space between glyphs) so each one can be read and edited in place.
//! Advances are proportional: a glyph is as wide as its set columns, plus one clear column.

/// Rows of a glyph cell: 7 down to the baseline, then 2 descender rows (g, j, p, q, y).
pub(super) const CELL_H: u32 = 9;
/// Columns of a glyph cell.
const CELL_W: usize = 5;
/// Width of a space, in font pixels: with the one-pixel gaps either side, words stand
/// four pixels apart.
const SPACE: u32 = 2;

/// A row of glyphs drawn as text.
struct Sheet {
    /// The characters, left to right.
    chars: &'static str,
    /// Pixel rows, top to bottom: `CELL_W` columns per glyph, one space between glyphs.
    rows: [&'static str; CELL_H as usize],
}

/// The glyphs: lower case, upper case, digits and punctuation, 13 or fewer a sheet.
const SHEETS: [Sheet; 6] = [
    Sheet {
        chars: "abcdefghijklm",
        rows: [
            "..... #.... ..... ....# ..... ..##. ..... #.... .#... ...#. #.... ##... .....",
            "..... #.... ..... ....# ..... .#... ..... #.... ..... ..... #.... .#... .....",
            ".###. ####. .#### .#### .###. ###.. .#### ####. ##... ..##. #..#. .#... ##.#.",
            "....# #...# #.... #...# #...# .#... #...# #...# .#... ...#. #.#.. .#... #.#.#",
            ".#### #...# #.... #...# ##### .#... #...# #...# .#... ...#. ##... .#... #.#.#",
            "#...# #...# #.... #...# #.... .#... #...# #...# .#... ...#. #.#.. .#... #.#.#",
            ".#### ####. .#### .#### .#### .#... .#### #...# ###.. ...#. #..#. ###.. #.#.#",
            "..... ..... ..... ..... ..... ..... ....# ..... ..... #..#. ..... ..... .....",
            "..... ..... ..... ..... ..... ..... .###. ..... ..... .##.. ..... ..... .....",
        ],
    },
    Sheet {
        chars: "nopqrstuvwxyz",
        rows: [
            "..... ..... ..... ..... ..... ..... .#... ..... ..... ..... ..... ..... .....",
            "..... ..... ..... ..... ..... ..... .#... ..... ..... ..... ..... ..... .....",
            "#.##. .###. ####. .#### #.##. .#### ###.. #...# #...# #...# #...# #...# #####",
            "##..# #...# #...# #...# ##..# #.... .#... #...# #...# #...# .#.#. #...# ...#.",
            "#...# #...# #...# #...# #.... .###. .#... #...# #...# #.#.# ..#.. #...# ..#..",
            "#...# #...# #...# #...# #.... ....# .#... #..## .#.#. #.#.# .#.#. #...# .#...",
            "#...# .###. ####. .#### #.... ####. ..##. .##.# ..#.. .#.#. #...# .#### #####",
            "..... ..... #.... ....# ..... ..... ..... ..... ..... ..... ..... ....# .....",
            "..... ..... #.... ....# ..... ..... ..... ..... ..... ..... ..... .###. .....",
        ],
    },
    Sheet {
        chars: "ABCDEFGHIJKLM",
        rows: [
            ".###. ####. .###. ####. ##### ##### .###. #...# ###.. ..### #...# #.... #...#",
            "#...# #...# #...# #...# #.... #.... #...# #...# .#... ...#. #..#. #.... ##.##",
            "#...# #...# #.... #...# #.... #.... #.... #...# .#... ...#. #.#.. #.... #.#.#",
            "##### ####. #.... #...# ####. ####. #.### ##### .#... ...#. ##... #.... #.#.#",
            "#...# #...# #.... #...# #.... #.... #...# #...# .#... ...#. #.#.. #.... #...#",
            "#...# #...# #...# #...# #.... #.... #...# #...# .#... #..#. #..#. #.... #...#",
            "#...# ####. .###. ####. ##### #.... .#### #...# ###.. .##.. #...# ##### #...#",
            "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
            "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
        ],
    },
    Sheet {
        chars: "NOPQRSTUVWXYZ",
        rows: [
            "#...# .###. ####. .###. ####. .#### ##### #...# #...# #...# #...# #...# #####",
            "#...# #...# #...# #...# #...# #.... ..#.. #...# #...# #...# #...# #...# ....#",
            "##..# #...# #...# #...# #...# #.... ..#.. #...# #...# #...# .#.#. .#.#. ...#.",
            "#.#.# #...# ####. #...# ####. .###. ..#.. #...# #...# #.#.# ..#.. ..#.. ..#..",
            "#..## #...# #.... #.#.# #.#.. ....# ..#.. #...# #...# #.#.# .#.#. ..#.. .#...",
            "#...# #...# #.... #..#. #..#. ....# ..#.. #...# .#.#. #.#.# #...# ..#.. #....",
            "#...# .###. #.... .##.# #...# ####. ..#.. .###. ..#.. .#.#. #...# ..#.. #####",
            "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
            "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
        ],
    },
    Sheet {
        chars: "0123456789",
        rows: [
            ".###. ..#.. .###. ##### ...#. ##### ..##. ##### .###. .###.",
            "#...# .##.. #...# ...#. ..##. #.... .#... ....# #...# #...#",
            "#..## ..#.. ....# ..#.. .#.#. ####. #.... ...#. #...# #...#",
            "#.#.# ..#.. ...#. ...#. #..#. ....# ####. ..#.. .###. .####",
            "##..# ..#.. ..#.. ....# ##### ....# #...# .#... #...# ....#",
            "#...# ..#.. .#... #...# ...#. #...# #...# .#... #...# ...#.",
            ".###. .###. ##### .###. ...#. .###. .###. .#... .###. .##..",
            "..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
            "..... ..... ..... ..... ..... ..... ..... ..... ..... .....",
        ],
    },
    Sheet {
        chars: ".,-+:/^=()|%_",
        rows: [
            "..... ..... ..... ..... ..... ....# ..#.. ..... ..#.. #.... #.... ##..# .....",
            "..... ..... ..... ..... ..... ....# .#.#. ..... .#... .#... #.... ##..# .....",
            "..... ..... ..... ..#.. #.... ...#. #...# ####. #.... ..#.. #.... ...#. .....",
            "..... ..... ###.. ..#.. ..... ..#.. ..... ..... #.... ..#.. #.... ..#.. .....",
            "..... ..... ..... ##### ..... .#... ..... ####. #.... ..#.. #.... .#... .....",
            "..... .#... ..... ..#.. ..... #.... ..... ..... .#... .#... #.... #..## .....",
            "#.... .#... ..... ..#.. #.... #.... ..... ..... ..#.. #.... #.... #..## .....",
            "..... #.... ..... ..... ..... ..... ..... ..... ..... ..... #.... ..... .....",
            "..... ..... ..... ..... ..... ..... ..... ..... ..... ..... #.... ..... #####",
        ],
    },
];

/// One glyph, trimmed to its set columns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Glyph {
    /// Row bits, bit `width - 1 - col` for column `col`.
    rows: [u8; CELL_H as usize],
    /// Columns from the first to the last set one (a space: [`SPACE`] clear columns).
    width: u32,
    /// Advance to the next glyph, in font pixels.
    advance: u32,
}

impl Glyph {
    /// Whether font pixel (`col`, `row`) is set.
    #[inline]
    #[must_use]
    pub(super) fn pixel(&self, col: u32, row: u32) -> bool {
        col < self.width
            && self
                .rows
                .get(row as usize)
                .is_some_and(|r| (r >> (self.width - 1 - col)) & 1 == 1)
    }

    /// Width in font pixels.
    #[inline]
    #[must_use]
    pub(super) fn width(&self) -> u32 {
        self.width
    }

    /// Drawn in place of a character without a glyph: a hollow box, so a missing glyph
    /// shows instead of vanishing.
    const MISSING: Self = Self {
        rows: [0b1111, 0b1001, 0b1001, 0b1001, 0b1001, 0b1001, 0b1111, 0, 0],
        width: 4,
        advance: 5,
    };

    const SPACE: Self = Self {
        rows: [0; CELL_H as usize],
        width: SPACE,
        advance: SPACE + 1,
    };
}

/// The glyph of `c`, `None` when the font lacks it. A space is a glyph with no pixels.
#[must_use]
pub(super) fn glyph(c: char) -> Option<Glyph> {
    if c == ' ' {
        return Some(Glyph::SPACE);
    }
    let (sheet, index) = SHEETS
        .iter()
        .find_map(|s| s.chars.chars().position(|k| k == c).map(|i| (s, i)))?;
    let start = index * (CELL_W + 1);
    let mut cols = [[false; CELL_W]; CELL_H as usize];
    for (row, text) in cols.iter_mut().zip(sheet.rows) {
        let cells = text.as_bytes().get(start..start + CELL_W)?;
        for (px, b) in row.iter_mut().zip(cells) {
            *px = *b == b'#';
        }
    }
    let used = |col: usize| cols.iter().any(|r| r.get(col).copied().unwrap_or(false));
    let left = (0..CELL_W).find(|&col| used(col))?;
    let right = (0..CELL_W).rev().find(|&col| used(col))?;
    let mut rows = [0_u8; CELL_H as usize];
    for (bits, row) in rows.iter_mut().zip(&cols) {
        for px in row.get(left..=right).unwrap_or(&[]) {
            *bits = (*bits << 1) | u8::from(*px);
        }
    }
    let width = (right - left + 1) as u32;
    Some(Glyph {
        rows,
        width,
        advance: width + 1,
    })
}

/// Glyphs of `s` with their left edges, in font pixels from the start of the text.
pub(super) fn layout(s: &str) -> impl Iterator<Item = (u32, Glyph)> + '_ {
    s.chars().scan(0_u32, |x, c| {
        let g = glyph(c).unwrap_or(Glyph::MISSING);
        let at = *x;
        *x += g.advance;
        Some((at, g))
    })
}

/// Width of `s` in font pixels: glyph widths plus one-pixel gaps between glyphs.
#[must_use]
pub(super) fn text_width(s: &str) -> u32 {
    layout(s).last().map_or(0, |(x, g)| x + g.width)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every character of the sheets, in sheet order.
    fn sheet_chars() -> impl Iterator<Item = char> {
        SHEETS.iter().flat_map(|s| s.chars.chars())
    }

    #[test]
    fn sheets_are_well_formed() {
        for sheet in &SHEETS {
            let n = sheet.chars.chars().count();
            for (r, row) in sheet.rows.iter().enumerate() {
                assert_eq!(row.len(), n * (CELL_W + 1) - 1, "{:?} row {r}", sheet.chars);
                for (i, b) in row.bytes().enumerate() {
                    let sep = i % (CELL_W + 1) == CELL_W;
                    let ok = if sep {
                        b == b' '
                    } else {
                        b == b'.' || b == b'#'
                    };
                    assert!(ok, "{:?} row {r} column {i}: {:?}", sheet.chars, b as char);
                }
            }
        }
        let mut seen: Vec<char> = sheet_chars().collect();
        let total = seen.len();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), total, "a character is in two sheets");
        assert!(!seen.contains(&' '), "space is built in, not drawn");
    }

    #[test]
    fn the_plot_character_set_is_covered() {
        let needed = ('a'..='z')
            .chain('A'..='Z')
            .chain('0'..='9')
            .chain(" .-:/^=()|,%".chars());
        for c in needed {
            assert!(glyph(c).is_some(), "no glyph for {c:?}");
        }
        assert_eq!(glyph('\u{e9}'), None, "no glyph for accented letters");
        assert_eq!(glyph('\t'), None, "no glyph for a tab");
    }

    /// Rows with a set pixel.
    fn rows_used(g: &Glyph) -> Vec<u32> {
        (0..CELL_H)
            .filter(|&r| (0..g.width()).any(|c| g.pixel(c, r)))
            .collect()
    }

    #[test]
    fn glyphs_sit_on_the_baseline() {
        let descenders = "gjpqy,_|";
        let x_height = "acegmnopqrsuvwxyz";
        for c in sheet_chars() {
            let g = glyph(c).unwrap_or(Glyph::MISSING);
            assert!(g != Glyph::MISSING, "{c:?} has no pixels");
            assert!(
                (1..=CELL_W as u32).contains(&g.width()),
                "{c:?} width {}",
                g.width()
            );
            let rows = rows_used(&g);
            let below = rows.iter().any(|&r| r >= 7);
            assert_eq!(
                below,
                descenders.contains(c),
                "{c:?} descender rows {rows:?}"
            );
            if c.is_ascii_alphanumeric() {
                assert!(
                    rows.contains(&6),
                    "{c:?} does not reach the baseline: {rows:?}"
                );
            }
            if c.is_ascii_uppercase() || c.is_ascii_digit() {
                assert!(rows.contains(&0), "{c:?} is not cap height: {rows:?}");
            }
            if x_height.contains(c) {
                assert!(
                    rows.iter().all(|&r| r >= 2),
                    "{c:?} above x-height: {rows:?}"
                );
            }
            // Trimmed: the first and last columns are used.
            for col in [0, g.width() - 1] {
                assert!(
                    (0..CELL_H).any(|r| g.pixel(col, r)),
                    "{c:?} column {col} empty"
                );
            }
        }
    }

    #[test]
    fn glyphs_are_distinct() {
        let all: Vec<(char, Glyph)> = sheet_chars()
            .filter_map(|c| glyph(c).map(|g| (c, g)))
            .collect();
        for (i, (a, ga)) in all.iter().enumerate() {
            for (b, gb) in all.iter().skip(i + 1) {
                assert_ne!(ga, gb, "{a:?} and {b:?} look the same");
            }
            assert_ne!(
                *ga,
                Glyph::MISSING,
                "{a:?} looks like the missing-glyph box"
            );
        }
    }

    #[test]
    fn width_adds_glyph_widths_and_one_pixel_gaps() {
        // Reference: count columns from the sheets' art directly.
        let art_width = |c: char| -> u32 {
            let Some((sheet, i)) = SHEETS
                .iter()
                .find_map(|s| s.chars.chars().position(|k| k == c).map(|i| (s, i)))
            else {
                return if c == ' ' { SPACE } else { 4 };
            };
            let cols: Vec<usize> = (0..CELL_W)
                .filter(|&col| {
                    let at = i * (CELL_W + 1) + col;
                    sheet
                        .rows
                        .iter()
                        .any(|r| r.as_bytes().get(at) == Some(&b'#'))
                })
                .collect();
            (cols.last().unwrap_or(&0) - cols.first().unwrap_or(&0) + 1) as u32
        };
        for s in [
            "a",
            "fixed64",
            "PSNR dB",
            "s0^2=1e-3",
            "(x)",
            "l1I|",
            "\u{e9}t\u{e9}",
        ] {
            let n = s.chars().count() as u32;
            let want: u32 = s.chars().map(art_width).sum::<u32>() + n - 1;
            assert_eq!(text_width(s), want, "{s:?}");
        }
        assert_eq!(text_width(""), 0, "empty text");
        assert_eq!(text_width(" "), SPACE, "a lone space keeps its width");
    }
}
