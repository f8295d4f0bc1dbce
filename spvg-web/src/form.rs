//! The page's inputs read as text and validated, natively testable: the settings fields
//! (a refused value is said, never replaced by a default) and the URL's `?check=` and
//! `?eq=` (a typo must fail the check, not run one frame and pass).

use crate::renderer::PAGE_MAX_BUDGET;

/// A whole number of at least `least`, or why not, naming the field.
///
/// # Errors
///
/// The message names `what` and the value as typed: empty, not a whole number, below
/// `least` or above `most`.
pub fn whole(what: &str, text: &str, least: u32, most: u32) -> Result<u32, String> {
    let t = text.trim();
    match t.parse::<u32>() {
        Ok(n) if (least..=most).contains(&n) => Ok(n),
        Ok(n) => Err(format!("{what} = {n} must be in [{least}, {most}]")),
        Err(_) if t.is_empty() => Err(format!("{what} is empty")),
        Err(_) => Err(format!(
            "{what} = \"{t}\" must be a whole number in [{least}, {most}]"
        )),
    }
}

/// The adaptive settings the form asks for: `sigma0^2` as typed (a positive finite
/// number, for example `5e-4`) and the budget `[min, max]` (whole numbers in
/// `[1, PAGE_MAX_BUDGET]`). The core's config check still judges the pair
/// (`min <= max`).
///
/// # Errors
///
/// The first refused field, named, with its value as typed.
pub fn settings(sigma: &str, min: &str, max: &str) -> Result<(f32, [u32; 2]), String> {
    let s = sigma.trim();
    let variance = match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => v,
        Ok(v) => return Err(format!("sigma0^2 = {v} must be finite and > 0")),
        Err(_) if s.is_empty() => return Err("sigma0^2 is empty".into()),
        Err(_) => return Err(format!("sigma0^2 = \"{s}\" is not a number")),
    };
    let lo = whole("budget min", min, 1, PAGE_MAX_BUDGET)?;
    let hi = whole("budget max", max, 1, PAGE_MAX_BUDGET)?;
    Ok((variance, [lo, hi]))
}

/// The largest `?check=N`: a check of more frames is a typo (the default is 48).
pub const MAX_CHECK_FRAMES: u32 = 10_000;

/// `?check=N`: a positive whole number of frames.
///
/// # Errors
///
/// A message saying what was given and what the check needs.
pub fn check_frames(text: &str) -> Result<u32, String> {
    whole("?check", text, 1, MAX_CHECK_FRAMES)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::{BUDGET, TARGET_VARIANCE};

    #[test]
    fn the_default_target_is_exact() {
        // The page's field holds "5e-4"; the value read is the documented constant, bit
        // for bit (a log-scale field of -3.3 read 5.01e-4).
        assert_eq!(
            settings("5e-4", "1", "64"),
            Ok((TARGET_VARIANCE, BUDGET)),
            "the form's defaults"
        );
        assert_eq!(TARGET_VARIANCE.to_bits(), 0.0005_f32.to_bits());
    }

    #[test]
    fn refused_fields_are_named_with_their_values() {
        let refused = |s: &str, lo: &str, hi: &str| settings(s, lo, hi).unwrap_err();
        assert!(refused("5e-4", "-5", "64").contains("budget min = \"-5\""));
        assert!(refused("5e-4", "1", "100000").contains("budget max = 100000"));
        assert!(refused("5e-4", "1", "257").contains("[1, 256]"));
        assert!(refused("5e-4", "1.5", "64").contains("whole number"));
        assert!(refused("", "1", "64").contains("sigma0^2 is empty"));
        assert!(refused("abc", "1", "64").contains("\"abc\" is not a number"));
        assert!(refused("inf", "1", "64").contains("must be finite"));
        assert!(refused("-1e-4", "1", "64").contains("> 0"));
        assert!(refused("0", "1", "64").contains("> 0"));
        assert_eq!(settings(" 1e-3 ", "2", "256"), Ok((1e-3, [2, 256])));
    }

    #[test]
    fn only_a_positive_whole_check_runs() {
        for bad in ["abc", "0", "-3", "", "1.5", "1e3", "99999999999"] {
            let e = check_frames(bad).unwrap_err();
            assert!(e.starts_with("?check"), "{bad}: {e}");
        }
        assert_eq!(check_frames("48"), Ok(48));
        assert_eq!(check_frames("1"), Ok(1));
    }
}
