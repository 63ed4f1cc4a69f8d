//! A set of faulty branch chains. Users write it as a comma-separated list of
//! chain numbers ("2,3,9", [`FaultSet::parse`]); reports and the source's
//! Table 1 label it by its digits in ascending order ("239", [`FaultSet::from_label`]).

use super::model::N_CHAINS;
use crate::{Error, ErrorKind, Result};
use std::fmt;

/// A set of branch chains (bit `i` is chain `i + 1`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FaultSet(pub u16);

impl FaultSet {
    /// The empty set (no fault).
    pub const EMPTY: FaultSet = FaultSet(0);

    /// The set of the given zero-based chain indices.
    pub fn from_indices(idx: &[usize]) -> Self {
        FaultSet(idx.iter().fold(0, |m, &i| m | (1 << i)))
    }

    /// Parse a list of chain numbers as a user writes it: the numbers 1–9
    /// separated by commas, spaces around them allowed (`"2,3,9"`,
    /// `"9, 2, 3"`). Order does not matter; a chain may not repeat.
    ///
    /// Anything else is an error rather than a guess: `"1234"` could mean
    /// chain 1234 or chains 1, 2, 3, 4, so a number outside 1–9 is refused
    /// with a hint, as are empty items (`"2,,3"`), repeats and other
    /// separators. (The compact form `"239"` that reports print is read by
    /// [`FaultSet::from_label`].)
    ///
    /// ```
    /// use clino::redundancy::fault_set::FaultSet;
    /// assert_eq!(FaultSet::parse("9, 2,3").unwrap().to_string(), "239");
    /// assert!(FaultSet::parse("1234").is_err());
    /// assert!(FaultSet::parse("2,2").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<Self> {
        let bad = |m: String| Err(Error::new(ErrorKind::InvalidInput, m));
        if s.trim().is_empty() {
            return bad(
                "no chain numbers: give the faulty chains 1–9 separated by commas, e.g. 2,3,9"
                    .into(),
            );
        }
        let mut m = 0u16;
        for item in s.split(',') {
            let item = item.trim();
            let n: u32 = match item.parse() {
                Ok(n) if item.chars().all(|c| c.is_ascii_digit()) => n,
                _ if item.is_empty() => {
                    return bad(format!(
                        "empty item in '{s}': give chain numbers 1–9 separated by commas, e.g. 2,3,9"
                    ));
                }
                _ => {
                    return bad(format!(
                        "'{item}' in '{s}' is not a chain number 1–9 (separate chains with commas, e.g. 2,3,9)"
                    ));
                }
            };
            if !(1..=N_CHAINS as u32).contains(&n) {
                let distinct = item
                    .chars()
                    .collect::<std::collections::BTreeSet<_>>()
                    .len()
                    == item.len();
                let hint =
                    if item.len() > 1 && distinct && item.chars().all(|c| ('1'..='9').contains(&c))
                    {
                        let digits: Vec<String> = item.chars().map(String::from).collect();
                        format!(
                            "; for chains {} write {}",
                            digits.join(", "),
                            digits.join(",")
                        )
                    } else {
                        String::new()
                    };
                return bad(format!(
                    "there is no chain {item}: chains are numbered 1–9{hint}"
                ));
            }
            let bit = 1 << (n - 1);
            if m & bit != 0 {
                return bad(format!("chain {n} is listed twice in '{s}'"));
            }
            m |= bit;
        }
        Ok(FaultSet(m))
    }

    /// Read the compact label reports print ([`Display`](fmt::Display)) and the
    /// source's Table 1 uses: the chain digits in ascending order, each once
    /// (`"239"`). Not for user input (see [`FaultSet::parse`]).
    pub fn from_label(s: &str) -> Result<Self> {
        let mut m = 0u16;
        let mut last = 0;
        for c in s.chars() {
            match c.to_digit(10) {
                Some(d @ 1..=9) if d > last => {
                    m |= 1 << (d - 1);
                    last = d;
                }
                _ => {
                    return Err(Error::new(
                        ErrorKind::InvalidInput,
                        format!("'{s}' is not a fault-set label (ascending chain digits 1–9)"),
                    ));
                }
            }
        }
        if m == 0 {
            return Err(Error::new(ErrorKind::InvalidInput, "empty fault-set label"));
        }
        Ok(FaultSet(m))
    }

    /// The chains as a comma-separated list, the form [`FaultSet::parse`] reads ("2,3,9").
    pub fn to_list(self) -> String {
        self.indices()
            .iter()
            .map(|i| (i + 1).to_string())
            .collect::<Vec<_>>()
            .join(",")
    }

    /// Number of chains in the set.
    pub fn len(self) -> usize {
        self.0.count_ones() as usize
    }

    /// True for the empty set.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// True if zero-based chain `i` is in the set.
    pub fn contains(self, i: usize) -> bool {
        self.0 & (1 << i) != 0
    }

    /// True if the two sets share a chain.
    pub fn intersects(self, other: FaultSet) -> bool {
        self.0 & other.0 != 0
    }

    /// Zero-based chain indices, ascending.
    pub fn indices(self) -> Vec<usize> {
        (0..N_CHAINS).filter(|&i| self.contains(i)).collect()
    }

    /// The chains not in the set, zero-based, ascending.
    pub fn complement_indices(self) -> Vec<usize> {
        (0..N_CHAINS).filter(|&i| !self.contains(i)).collect()
    }

    /// All sets of exactly `k` chains, in lexicographic order of their digits.
    pub fn all_of_size(k: usize) -> Vec<FaultSet> {
        let mut v: Vec<FaultSet> = (0u16..1 << N_CHAINS)
            .map(FaultSet)
            .filter(|s| s.len() == k)
            .collect();
        v.sort_by_key(|s| s.to_string());
        v
    }
}

impl fmt::Display for FaultSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for i in self.indices() {
            write!(f, "{}", i + 1)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_and_print_round_trip() {
        let s = FaultSet::parse("9,2, 3").unwrap();
        assert_eq!(s.to_string(), "239");
        assert_eq!(s.to_list(), "2,3,9");
        assert_eq!(FaultSet::parse(&s.to_list()).unwrap(), s);
        assert_eq!(FaultSet::from_label("239").unwrap(), s);
        assert_eq!(s.indices(), vec![1, 2, 8]);
        assert_eq!(FaultSet::parse(" 7 ").unwrap().to_list(), "7");
    }

    #[test]
    fn ambiguous_or_malformed_lists_are_refused() {
        // "1234" is not read digit by digit as chains 1, 2, 3, 4
        let e = FaultSet::parse("1234").unwrap_err();
        assert!(e.message.contains("no chain 1234"), "{e}");
        assert!(e.message.contains("write 1,2,3,4"), "{e}");
        for s in [
            "", " ", "20", "0", "2,,3", "2,3,", "2;3", "2 3", "a", "2,2", "-1", "+2", "2.0",
        ] {
            assert!(FaultSet::parse(s).is_err(), "{s:?}");
        }
        for s in ["", "20", "32", "2,3", "none"] {
            assert!(FaultSet::from_label(s).is_err(), "{s:?}");
        }
    }

    #[test]
    fn binomial_counts() {
        let n: Vec<usize> = (0..=4).map(|k| FaultSet::all_of_size(k).len()).collect();
        assert_eq!(n, vec![1, 9, 36, 84, 126]);
        assert_eq!(FaultSet::all_of_size(2)[0].to_string(), "12");
    }
}
