//! Putting things in order by a real number, written once. Every sort of
//! the core by a range, a bearing, a score or a time goes through
//! [`sort_keyed`], so that the wasm holds one sort routine instead of one
//! per call site (each stable sort of its own costs about 5 KB of code).

/// Sorts `keyed` ascending by key ([`f64::total_cmp`]), equal keys by
/// their tie-breaker: the order is total, so the result is the same
/// whatever sort produces it.
pub fn sort_keyed(keyed: &mut [(f64, usize)]) {
    keyed.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
}

/// Sorts `items` ascending by `key` ([`f64::total_cmp`]), items of equal
/// keys kept in the order they came in (a stable sort). For a descending
/// order, negate the key: negation reverses the total order exactly.
pub fn sort_stable_by_key<T: Copy>(items: &mut [T], key: impl Fn(&T) -> f64) {
    let mut keyed: Vec<(f64, usize)> = items
        .iter()
        .enumerate()
        .map(|(i, item)| (key(item), i))
        .collect();
    sort_keyed(&mut keyed);
    let sorted: Vec<T> = keyed.iter().map(|&(_, i)| items[i]).collect();
    items.copy_from_slice(&sorted);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_keys_keep_their_order_and_negated_keys_reverse() {
        let mut items: [(f64, char); 6] = [
            (2.0, 'a'),
            (1.0, 'b'),
            (2.0, 'c'),
            (-0.0, 'd'),
            (0.0, 'e'),
            (1.0, 'f'),
        ];
        let mut stable = items;
        stable.sort_by(|a, b| a.0.total_cmp(&b.0));
        sort_stable_by_key(&mut items, |p| p.0);
        assert_eq!(items, stable);
        let mut descending = items;
        stable.sort_by(|a, b| b.0.total_cmp(&a.0));
        sort_stable_by_key(&mut descending, |p| -p.0);
        assert_eq!(descending, stable);
    }
}
