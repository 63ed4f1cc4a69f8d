//! A set of faulty branch chains, written as its chain numbers in ascending
//! order ("239" for chains 2, 3 and 9).

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

    /// Parse "2,3,9", "2 3 9" or "239" (chain numbers 1–9).
    pub fn parse(s: &str) -> Result<Self> {
        let mut m = 0u16;
        let digits: Vec<char> = s
            .chars()
            .filter(|c| !matches!(c, ',' | ' ' | ';'))
            .collect();
        if digits.is_empty() {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("no chain numbers in '{s}'"),
            ));
        }
        for c in digits {
            match c.to_digit(10) {
                Some(d @ 1..=9) => m |= 1 << (d - 1),
                _ => {
                    return Err(Error::new(
                        ErrorKind::InvalidInput,
                        format!("'{c}' in '{s}' is not a chain number 1–9"),
                    ));
                }
            }
        }
        Ok(FaultSet(m))
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
        assert_eq!(FaultSet::parse("239").unwrap(), s);
        assert_eq!(s.indices(), vec![1, 2, 8]);
        assert!(FaultSet::parse("20").is_err());
        assert!(FaultSet::parse("").is_err());
    }

    #[test]
    fn binomial_counts() {
        let n: Vec<usize> = (0..=4).map(|k| FaultSet::all_of_size(k).len()).collect();
        assert_eq!(n, vec![1, 9, 36, 84, 126]);
        assert_eq!(FaultSet::all_of_size(2)[0].to_string(), "12");
    }
}
