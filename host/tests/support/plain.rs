//! What every translated line must be: words of one capital letter and a
//! plain decimal number (`G01`, `X-1.2500`, `G54.1`), so never `inf`, `NaN`
//! or an exponent. Shared by the property test (`tests/finite.rs`) and the
//! fuzz target `translate` (`host/fuzz`), which include this file by path.

/// The first word of `line` that is not a capital letter and a plain
/// decimal number, if there is one.
pub fn odd_word(line: &str) -> Option<&str> {
    line.split(' ').find(|word| !is_plain(word))
}

fn is_plain(word: &str) -> bool {
    let Some(number) = word.strip_prefix(|c: char| c.is_ascii_uppercase()) else { return false };
    let unsigned = number.strip_prefix('-').unwrap_or(number);
    let (whole, fraction) = unsigned.split_once('.').unwrap_or((unsigned, "0"));
    let digits = |part: &str| !part.is_empty() && part.bytes().all(|b| b.is_ascii_digit());
    digits(whole) && digits(fraction)
}

#[cfg(test)]
mod tests {
    use super::odd_word;

    #[test]
    fn plain_words_pass_and_others_are_named() {
        assert_eq!(odd_word("N12 G02 X-1.2500 Y0.0000 I0.5000 J-0.0001 F11.8110"), None);
        assert_eq!(odd_word("G54.1 P3"), None);
        assert_eq!(odd_word("M62 P1"), None);
        assert_eq!(odd_word("G00 Xinf"), Some("Xinf"));
        assert_eq!(odd_word("G00 X-inf"), Some("X-inf"));
        assert_eq!(odd_word("G01 XNaN"), Some("XNaN"));
        assert_eq!(odd_word("S1e20"), Some("S1e20"));
        assert_eq!(odd_word("G01 X1.5e-7"), Some("X1.5e-7"));
        assert_eq!(odd_word("G01 X1."), Some("X1."));
        assert_eq!(odd_word("G01  X1"), Some(""));
        assert_eq!(odd_word("g01"), Some("g01"));
    }
}
