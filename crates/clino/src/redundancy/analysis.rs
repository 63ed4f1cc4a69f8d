//! Which fault sets can be restored and isolated, from the equations alone
//! (Li Chenggang et al., "Fault Diagnosis in a Gyroscope-Based Six-Axis
//! Accelerometer", section 3 and Table 1).
//!
//! ## General scheme (linear parity space)
//!
//! Per sample the nine forces and the gyro obey six independent linear
//! relations, `P·f = (0, c·ε*)` ([`SixAxisAccelerometer::parity`]). A fault
//! `e` on the chains of a set `F` moves the base residuals by `P_F·e_F`.
//!
//! * **Restorable (location known)**: `f_F` is unique given the healthy
//!   chains and the gyro iff `P_F` has full column rank `|F|`
//!   (equivalently, the healthy chains and the gyro still determine the
//!   six-dimensional acceleration).
//! * **Isolable**: restorable, and no other set `S` with `|S| ≤ |F|` explains
//!   every fault of `F`, i.e. `range(P_F) ⊄ range(P_S)`; with the
//!   smallest-set rule the diagnosis then returns `F` for generic faults.
//!
//! ## The source's scheme
//!
//! * **Restorable**: chains are replaced one at a time from a relation of
//!   [`source_relations`] in which they are the only unrestored faulty chain
//!   (eq 14 is three such steps), repeating until none is left.
//! * **Isolable**: each of the 24 relations is judged satisfied or not; the
//!   faulty set is read off the pattern (the source's "Descartes coordinate
//!   systems"). `F` is isolable iff no other set of at most `|F|` chains
//!   violates exactly the same relations.
//!
//! ## Results and the differences from the source
//!
//! The source states 165 restorable fault conditions: all 9 single, 36 double,
//! 84 triple faults and the 36 quadruples of its Table 1. clino computes
//! (`clino redundancy analyze`, tested below):
//!
//! | size | general restorable | general isolable | source restorable | source isolable | source claims |
//! |---|---|---|---|---|---|
//! | 1 | 9 | 9 | 9 | 9 | 9 |
//! | 2 | 36 | 36 | 36 | 33 | 36 |
//! | 3 | 84 | 84 | 83 | 53 | 84 |
//! | 4 | 126 | 96 | 120 | **36 = Table 1** | 36 |
//!
//! * **Table 1 is exactly the set of quadruples the source's own 24-relation
//!   scheme isolates.** Every Table 1 quadruple (24 with one normal chain
//!   1, 5 or 9; 12 with none) is also isolable by the general scheme, which
//!   isolates 60 more (96 in all): the 36 isolable quadruples with two normal
//!   chains, and 24 with one normal chain that shares each of its two
//!   compatibility equations with another faulty chain (e.g. 1236: chain 1
//!   with 2 in (a) and with 3 in (b)). The source's relations always take two
//!   normal chains as references, so its scheme cannot separate these; the
//!   full parity space can.
//! * The 30 quadruples the general scheme cannot isolate (12 with one normal
//!   chain, 9 with two, all 6 with three, 3 with none) share their fault
//!   directions with another quadruple (e.g. 1234 and 1237, 2347 and 1234):
//!   they are restorable if the location is known, but no residual can tell
//!   which of the two sets failed. Three of them (2347, 2468, 3678: two
//!   complete gyro pairs) are the only quadruples without a normal chain
//!   that Table 1 lacks.
//! * For sizes 2 and 3 the source claims all sets. Its own Boolean scheme
//!   isolates only 33 doubles (not 15, 19, 59: two normal chains) and 53
//!   triples, although all are restorable; the general scheme isolates all 36
//!   and 84, so the claim holds for the general scheme (and the simulation
//!   confirms it), not for the boolean reading of the 24 relations.
//! * All 126 quadruples are restorable when their location is known (the
//!   source counts only those it can also diagnose); sequential replacement
//!   with the source's relations reaches 120 of them, and 83 of the 84
//!   triples: not 159, because every one of its relations holds at least two
//!   of the three normal chains (the general least-squares restoration does
//!   restore 159).
//! * The counts do not depend on the stiffnesses, mass or size (tested with
//!   uneven stiffnesses): they follow from the structure of eqs 10 and 12.

use super::equations::{Relation, source_relations};
use super::fault_set::FaultSet;
use super::model::SixAxisAccelerometer;
use nalgebra::DMatrix;
use std::collections::BTreeMap;

/// The source's Table 1: quadruples it states restorable.
pub const TABLE1: [&str; 36] = [
    "1246", "1248", "1268", "1367", "1368", "1378", "1468", "1678", "2345", "2346", "2348", "2349",
    "2357", "2367", "2368", "2378", "2379", "2457", "2467", "2469", "2478", "2479", "2489", "2678",
    "2689", "3457", "3467", "3468", "3478", "3479", "3567", "3568", "3578", "4678", "4689", "5678",
];

/// Fault sets by size: size → sets (each written like "2389").
pub type SetsBySize = BTreeMap<String, Vec<String>>;

/// The analysis of restorable and isolable sets for sizes 1 to `max_size`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Analysis {
    /// General scheme: restorable when the location is known.
    pub restorable: SetsBySize,
    /// General scheme: isolable from the residuals (smallest explaining set).
    pub isolable: SetsBySize,
    /// The source's scheme: restorable by sequential replacement.
    pub source_restorable: SetsBySize,
    /// The source's scheme: isolable from the pattern of violated relations.
    pub source_isolable: SetsBySize,
    /// The source's Table 1 quadruples.
    pub table1: Vec<String>,
}

/// Numerical rank with a relative tolerance.
pub(crate) fn rank(m: &DMatrix<f64>) -> usize {
    if m.ncols() == 0 || m.nrows() == 0 {
        return 0;
    }
    let sv = m.clone().svd(false, false).singular_values;
    let max = sv.iter().fold(0.0f64, |a, &b| a.max(b));
    sv.iter().filter(|&&s| s > 1e-9 * max).count()
}

/// `P` with its compatibility rows scaled by the mean stiffness so that all
/// entries are of order one (ranks do not change, tolerances behave).
pub(crate) fn scaled_parity(acc: &SixAxisAccelerometer) -> DMatrix<f64> {
    let p = acc.parity();
    let kbar = acc.stiffness_n_m.iter().sum::<f64>() / 9.0;
    let mut d = DMatrix::from_iterator(6, 9, p.iter().copied());
    for r in 0..3 {
        for c in 0..9 {
            d[(r, c)] *= kbar;
        }
    }
    d
}

pub(crate) fn columns(p: &DMatrix<f64>, s: FaultSet) -> DMatrix<f64> {
    let idx = s.indices();
    DMatrix::from_fn(p.nrows(), idx.len(), |r, c| p[(r, idx[c])])
}

/// General restorability: `rank(P_F) = |F|`.
pub fn restorable(acc: &SixAxisAccelerometer, f: FaultSet) -> bool {
    rank(&columns(&scaled_parity(acc), f)) == f.len()
}

/// General isolability: restorable and `range(P_F) ⊄ range(P_S)` for every
/// other `S` with `|S| ≤ |F|`.
pub fn isolable(acc: &SixAxisAccelerometer, f: FaultSet) -> bool {
    let p = scaled_parity(acc);
    let k = f.len();
    if rank(&columns(&p, f)) != k {
        return false;
    }
    // only |S| = |F| can contain a k-dimensional range
    FaultSet::all_of_size(k)
        .into_iter()
        .filter(|&s| s != f)
        .all(|s| rank(&columns(&p, FaultSet(s.0 | f.0))) > rank(&columns(&p, s)))
}

/// The other sets of `|F|` chains whose fault space contains every fault of
/// `F` (`range(P_F) ⊆ range(P_S)`): a fault on `F` is explained by each of
/// them as well, so no residual can tell them apart. Empty exactly when a
/// restorable `F` is isolable ([`isolable`]); e.g. 1234 → \[1237\].
pub fn confusable_with(acc: &SixAxisAccelerometer, f: FaultSet) -> Vec<FaultSet> {
    let p = scaled_parity(acc);
    FaultSet::all_of_size(f.len())
        .into_iter()
        .filter(|&s| s != f)
        .filter(|&s| rank(&columns(&p, FaultSet(s.0 | f.0))) == rank(&columns(&p, s)))
        .collect()
}

/// What the general scheme can do about a fault on the chains `f`.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Capability {
    /// The healthy chains and the gyro determine `f`'s forces once its location is known.
    pub restorable: bool,
    /// The diagnosis can locate `f` (restorable, and no other set of as many chains explains it).
    pub isolable: bool,
    /// The sets a fault on `f` cannot be told from (labels, e.g. "1237").
    pub confusable_with: Vec<String>,
}

impl Capability {
    /// The capability of `f` on the device `acc`.
    pub fn of(acc: &SixAxisAccelerometer, f: FaultSet) -> Self {
        let restorable = restorable(acc, f);
        let confusable: Vec<String> = if restorable {
            confusable_with(acc, f)
                .iter()
                .map(|s| s.to_string())
                .collect()
        } else {
            Vec::new()
        };
        Self {
            restorable,
            isolable: restorable && confusable.is_empty(),
            confusable_with: confusable,
        }
    }

    /// A warning for a set the diagnosis cannot locate or the restoration cannot
    /// undo (`None` when it can do both).
    pub fn warning(&self, f: FaultSet) -> Option<String> {
        if !self.restorable {
            Some(format!(
                "chains {} cannot be restored: the healthy chains and the gyro do not determine their forces (see `clino redundancy analyze`)",
                f.to_list()
            ))
        } else if !self.isolable {
            let others: Vec<String> = self
                .confusable_with
                .iter()
                .map(|l| FaultSet::from_label(l).map_or_else(|_| l.clone(), |s| s.to_list()))
                .collect();
            Some(format!(
                "chains {} are not isolable: a fault on them is explained as well by chains {} (the same fault directions), so no diagnosis can locate it and a restoration may replace the wrong chains (see `clino redundancy analyze`)",
                f.to_list(),
                others.join(" or ")
            ))
        } else {
            None
        }
    }
}

/// Source-scheme restorability: sequential replacement through relations
/// with a single unrestored faulty chain.
pub fn source_restorable(relations: &[Relation], f: FaultSet) -> bool {
    let mut bad = f.0;
    loop {
        if bad == 0 {
            return true;
        }
        let step = relations
            .iter()
            .find(|r| (r.chains.0 & bad).count_ones() == 1);
        match step {
            Some(r) => bad &= !r.chains.0,
            None => return false,
        }
    }
}

/// The pattern of violated relations a fault set produces (bit per relation).
pub fn signature(relations: &[Relation], f: FaultSet) -> u32 {
    relations
        .iter()
        .enumerate()
        .filter(|(_, r)| r.chains.intersects(f))
        .fold(0, |m, (i, _)| m | (1 << i))
}

/// Source-scheme isolability: no other set of at most `|F|` chains violates
/// the same relations.
pub fn source_isolable(relations: &[Relation], f: FaultSet) -> bool {
    let sig = signature(relations, f);
    (1..=f.len()).all(|k| {
        FaultSet::all_of_size(k)
            .into_iter()
            .all(|s| s == f || signature(relations, s) != sig)
    })
}

/// Analyse sizes 1..=`max_size` for the device `acc`.
pub fn analyze(acc: &SixAxisAccelerometer, max_size: usize) -> Analysis {
    let rel = source_relations(acc);
    let mut a = Analysis {
        restorable: BTreeMap::new(),
        isolable: BTreeMap::new(),
        source_restorable: BTreeMap::new(),
        source_isolable: BTreeMap::new(),
        table1: TABLE1.iter().map(|s| s.to_string()).collect(),
    };
    for k in 1..=max_size {
        let sets = FaultSet::all_of_size(k);
        let pick = |pred: &dyn Fn(FaultSet) -> bool| -> Vec<String> {
            sets.iter()
                .filter(|&&s| pred(s))
                .map(|s| s.to_string())
                .collect()
        };
        a.restorable
            .insert(k.to_string(), pick(&|s| restorable(acc, s)));
        a.isolable
            .insert(k.to_string(), pick(&|s| isolable(acc, s)));
        a.source_restorable
            .insert(k.to_string(), pick(&|s| source_restorable(&rel, s)));
        a.source_isolable
            .insert(k.to_string(), pick(&|s| source_isolable(&rel, s)));
    }
    a
}

impl Analysis {
    /// For each size (in order), the sets that are restorable but not
    /// isolable by the general scheme: restorable when told where the fault
    /// is, but the residuals cannot say where. Sizes without any are left out.
    pub fn restorable_not_isolable(&self) -> Vec<(String, Vec<String>)> {
        let empty = Vec::new();
        self.restorable
            .iter()
            .filter_map(|(k, sets)| {
                let iso = self.isolable.get(k).unwrap_or(&empty);
                let not_iso: Vec<String> =
                    sets.iter().filter(|s| !iso.contains(s)).cloned().collect();
                (!not_iso.is_empty()).then(|| (k.clone(), not_iso))
            })
            .collect()
    }

    /// A short table of the counts and the Table 1 comparison.
    pub fn summary(&self) -> String {
        let n = |m: &SetsBySize, k: &str| m.get(k).map_or(0, |v| v.len());
        let mut s =
            String::from("size  restorable  isolable  source-restorable  source-isolable\n");
        for k in self.restorable.keys() {
            s += &format!(
                "{k:>4}  {:>10}  {:>8}  {:>17}  {:>15}\n",
                n(&self.restorable, k),
                n(&self.isolable, k),
                n(&self.source_restorable, k),
                n(&self.source_isolable, k)
            );
        }
        if let (Some(iso), Some(src)) = (self.isolable.get("4"), self.source_isolable.get("4")) {
            let in_iso = self.table1.iter().filter(|t| iso.contains(t)).count();
            let same =
                src.len() == self.table1.len() && self.table1.iter().all(|t| src.contains(t));
            s += &format!(
                "Table 1 (36 quadruples): {in_iso} isolable by the general scheme; source scheme reproduces it exactly: {}\n",
                if same { "yes" } else { "no" }
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(m: &SetsBySize) -> Vec<usize> {
        m.values().map(|v| v.len()).collect()
    }

    #[test]
    fn counts_and_table1() {
        let a = analyze(&SixAxisAccelerometer::reference(), 4);
        assert_eq!(counts(&a.restorable), vec![9, 36, 84, 126]);
        assert_eq!(counts(&a.isolable), vec![9, 36, 84, 96]);
        assert_eq!(counts(&a.source_restorable), vec![9, 36, 83, 120]);
        assert!(!a.source_restorable["3"].contains(&"159".to_string()));
        assert_eq!(counts(&a.source_isolable), vec![9, 33, 53, 36]);
        let mut src4 = a.source_isolable["4"].clone();
        src4.sort();
        assert_eq!(src4, TABLE1.to_vec());
        for t in TABLE1 {
            assert!(a.isolable["4"].contains(&t.to_string()), "{t}");
        }
        // the paper's 165 = 9 + 36 + 84 + 36
        let total: usize = ["1", "2", "3"]
            .iter()
            .map(|k| a.isolable[*k].len())
            .sum::<usize>()
            + TABLE1.len();
        assert_eq!(total, 165);
        assert!(!a.source_isolable["2"].contains(&"15".to_string()));
        assert!(!a.isolable["4"].contains(&"1234".to_string()));
    }

    #[test]
    fn counts_do_not_depend_on_stiffness() {
        let k: [f64; 9] = std::array::from_fn(|i| 1.0e7 * (1.0 + 0.37 * i as f64));
        let acc = SixAxisAccelerometer::new(0.3, 0.02, k).unwrap();
        let a = analyze(&acc, 4);
        assert_eq!(counts(&a.isolable), vec![9, 36, 84, 96]);
        assert_eq!(counts(&a.source_isolable), vec![9, 33, 53, 36]);
    }

    #[test]
    fn capability_names_the_sets_a_fault_is_confused_with() {
        let acc = SixAxisAccelerometer::reference();
        let c = Capability::of(&acc, FaultSet::from_label("1234").unwrap());
        assert!(c.restorable && !c.isolable, "{c:?}");
        assert!(c.confusable_with.contains(&"1237".to_string()), "{c:?}");
        let w = c.warning(FaultSet::from_label("1234").unwrap()).unwrap();
        assert!(w.contains("not isolable") && w.contains("1,2,3,7"), "{w}");
        let c = Capability::of(&acc, FaultSet::from_label("239").unwrap());
        assert!(
            c.isolable
                && c.confusable_with.is_empty()
                && c.warning(FaultSet(0b1_0000_0110)).is_none()
        );
        // seven chains: not restorable (six relations for seven unknown forces)
        let five = FaultSet::from_label("1234567").unwrap();
        let c = Capability::of(&acc, five);
        assert!(!c.restorable && !c.isolable);
        assert!(c.warning(five).unwrap().contains("cannot be restored"));
        // agrees with the counts: exactly the 96 isolable quadruples have no partner
        let n = FaultSet::all_of_size(4)
            .into_iter()
            .filter(|&s| restorable(&acc, s) && confusable_with(&acc, s).is_empty())
            .count();
        assert_eq!(n, 96);
    }

    #[test]
    fn non_isolable_pair_has_equal_ranges() {
        // 1234 and 1237: chain 7's direction lies in the span of 1, 2, 3, 4
        let p = scaled_parity(&SixAxisAccelerometer::reference());
        let u = FaultSet::from_label("12347").unwrap();
        assert_eq!(rank(&columns(&p, u)), 4);
    }
}
