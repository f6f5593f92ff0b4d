//! Visibility bitsets over lights: `u64` words, bit j = light j. Word-wide helpers for the
//! per-pixel loops, and [`Rows`] / [`RowsMut`]: one bitset per pixel in one flat array.

/// A flat array of bitsets of `words` words each, end to end (no vector per pixel), read by
/// row: row `i` is words `i·words .. (i+1)·words`. A view borrowed for the loop that reads
/// it, with the width the loop already holds ([`rows`]): the compiler sees the same slices and
/// indices as hand-written ones (no bounds check more), and rows of several arrays viewed with
/// one width have one length.
#[derive(Clone, Copy)]
pub struct Rows<'a> {
    bits: &'a [u64],
    words: usize,
}

/// [`Rows`] to write ([`rows_mut`]).
pub struct RowsMut<'a> {
    bits: &'a mut [u64],
    words: usize,
}

/// `bits` as rows of `words` words.
#[inline]
pub fn rows(bits: &[u64], words: usize) -> Rows<'_> {
    Rows { bits, words }
}

/// `bits` as rows of `words` words, to write.
#[inline]
pub fn rows_mut(bits: &mut [u64], words: usize) -> RowsMut<'_> {
    RowsMut { bits, words }
}

impl<'a> Rows<'a> {
    /// Number of rows.
    #[inline]
    pub fn len(self) -> usize {
        self.bits.len() / self.words.max(1)
    }

    /// Whether there is no row.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.len() == 0
    }

    /// Words per row.
    #[inline]
    pub fn words(self) -> usize {
        self.words
    }

    /// Row `i`.
    #[inline]
    pub fn row(self, i: usize) -> &'a [u64] {
        let w = self.words;
        &self.bits[i * w..(i + 1) * w]
    }

    /// Word `m` of row `i`.
    #[inline]
    pub fn word(self, i: usize, m: usize) -> u64 {
        debug_assert!(m < self.words);
        self.bits[i * self.words + m]
    }
}

impl<'a> RowsMut<'a> {
    /// Row `i`.
    #[inline]
    pub fn row(&self, i: usize) -> &[u64] {
        let w = self.words;
        &self.bits[i * w..(i + 1) * w]
    }

    /// Row `i`, to write.
    #[inline]
    pub fn row_mut(&mut self, i: usize) -> &mut [u64] {
        let w = self.words;
        &mut self.bits[i * w..(i + 1) * w]
    }

    /// Row `i`, to write, for as long as the array is borrowed.
    #[inline]
    pub fn into_row(self, i: usize) -> &'a mut [u64] {
        let w = self.words;
        &mut self.bits[i * w..(i + 1) * w]
    }

    /// Word `m` of row `i`, to write.
    #[inline]
    pub fn word_mut(&mut self, i: usize, m: usize) -> &mut u64 {
        debug_assert!(m < self.words);
        &mut self.bits[i * self.words + m]
    }

    /// Copies row `from` over row `to`.
    #[inline]
    pub fn copy_row(&mut self, from: usize, to: usize) {
        let w = self.words;
        self.bits.copy_within(from * w..(from + 1) * w, to * w);
    }
}

/// Sets bit `j`.
#[inline]
pub fn set(bits: &mut [u64], j: usize) {
    bits[j >> 6] |= 1 << (j & 63);
}

/// Clears bit `j`.
#[inline]
pub fn clear(bits: &mut [u64], j: usize) {
    bits[j >> 6] &= !(1 << (j & 63));
}

/// Reads bit `j`.
#[inline]
pub fn get(bits: &[u64], j: usize) -> bool {
    bits[j >> 6] >> (j & 63) & 1 == 1
}

/// Number of set bits.
#[inline]
pub fn count(bits: &[u64]) -> u32 {
    bits.iter().map(|w| w.count_ones()).sum()
}

/// Calls `f(j)` for every set bit, in increasing order.
#[inline]
pub fn for_each(bits: &[u64], mut f: impl FnMut(usize)) {
    for (w, &word) in bits.iter().enumerate() {
        let mut m = word;
        while m != 0 {
            let b = m.trailing_zeros() as usize;
            f(w * 64 + b);
            m &= m - 1;
        }
    }
}

/// Per light, whether at least `k` of the given words have the bit set (k in 0..=4):
/// a bit-sliced counter over up to four voters, one word at a time.
#[inline]
pub fn at_least(words: &[u64], k: u32) -> u64 {
    // ones, twos, fours: the count's binary digits per bit position.
    let (mut ones, mut twos, mut fours) = (0u64, 0u64, 0u64);
    for &w in words {
        let carry1 = ones & w;
        ones ^= w;
        let carry2 = twos & carry1;
        twos ^= carry1;
        fours |= carry2;
    }
    match k {
        0 => !0,
        1 => ones | twos | fours,
        2 => twos | fours,
        3 => (twos & ones) | fours,
        4 => fours,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_least_counts_voters_per_bit() {
        let words = [0b1111u64, 0b0111, 0b0011, 0b0001];
        assert_eq!(at_least(&words, 1), 0b1111);
        assert_eq!(at_least(&words, 2), 0b0111);
        assert_eq!(at_least(&words, 3), 0b0011);
        assert_eq!(at_least(&words, 4), 0b0001);
        assert_eq!(at_least(&words[..2], 2), 0b0111);
        assert_eq!(at_least(&[], 1), 0);
    }

    /// Every combination of up to four voters, one per bit position: bit b holds the voters
    /// whose index is set in b. Each (n, k) is checked against a popcount, and every wrong
    /// (n, k) is reported, not just the first.
    #[test]
    fn at_least_is_k_of_n_for_every_voter_combination() {
        let mut failures = Vec::new();
        for n in 0..=4usize {
            let words: Vec<u64> = (0..n)
                .map(|v| {
                    (0..16u32)
                        .filter(|b| b >> v & 1 == 1)
                        .fold(0, |w, b| w | 1 << b)
                })
                .collect();
            for k in 0..=4u32 {
                let got = at_least(&words, k);
                // Positions 16.. have no voter: at least k of them only for k = 0.
                let mut want = if k == 0 { !0u64 << 16 } else { 0 };
                for b in 0..16u32 {
                    let voters = (b & ((1 << n) - 1)).count_ones();
                    if voters >= k {
                        want |= 1 << b;
                    }
                }
                if got != want {
                    failures.push(format!("n {n} k {k}: got {got:#x}, want {want:#x}"));
                }
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }

    #[test]
    fn rows_are_words_end_to_end() {
        let mut v = vec![0u64; 6];
        let mut r = rows_mut(&mut v, 2);
        r.row_mut(1).copy_from_slice(&[5, 6]);
        *r.word_mut(2, 1) = 9;
        r.copy_row(1, 0);
        assert_eq!(r.row(0), [5, 6]);
        r.into_row(2)[0] = 7;
        let r = rows(&v, 2);
        assert_eq!(
            (r.row(1), r.word(1, 1), r.row(2)),
            (&[5, 6][..], 6, &[7, 9][..])
        );
        assert_eq!(v, [5, 6, 5, 6, 7, 9]);
    }

    #[test]
    fn set_get_iterate() {
        let mut b = vec![0u64; 3];
        for j in [0, 63, 64, 130, 191] {
            set(&mut b, j);
        }
        assert!(get(&b, 130) && !get(&b, 129));
        let mut seen = Vec::new();
        for_each(&b, |j| seen.push(j));
        assert_eq!(seen, [0, 63, 64, 130, 191]);
        assert_eq!(count(&b), 5);
        clear(&mut b, 64);
        assert!(!get(&b, 64));
    }
}
