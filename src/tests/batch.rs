//! The shard rule of batch work (`--shard i/n`): frames and bench jobs.

use crate::batch::Shard;
use proptest::prelude::*;

proptest! {
    /// The rule every shard follows: for any list length and shard count,
    /// the shards' items (frames) and jobs (bench) are disjoint, together
    /// are the unsharded list, and differ in size by at most one.
    #[test]
    fn shards_partition_every_list(len in 0usize..300, n in 1usize..24, algebras in 1usize..4) {
        let mut seen = vec![0u32; len];
        let mut sizes = Vec::new();
        for i in 0..n {
            let s = Shard::new(i, n).unwrap();
            let items: Vec<usize> = s.items(len).collect();
            prop_assert!(items.iter().all(|&k| s.contains(k) && k % n == i));
            for &k in &items {
                seen[k] += 1;
            }
            sizes.push(items.len());
        }
        prop_assert!(seen.iter().all(|&c| c == 1));
        prop_assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1);
        let surfaces: Vec<String> = (0..len.min(40)).map(|k| format!("s{k}")).collect();
        let algs: Vec<String> = ["ia", "raa", "auto"][..algebras].iter().map(|a| a.to_string()).collect();
        let all = crate::bench::jobs(&surfaces, &algs);
        let mut union: Vec<_> = (0..n).flat_map(|i| crate::bench::shard(&all, Shard::new(i, n).unwrap())).collect();
        union.sort_by_key(|j| j.index);
        prop_assert_eq!(union, all);
    }
}
