//! Vectors compared and copied by their bits, as the solver's kept
//! results need: whether a state is the one a result was kept at, and
//! copies that cost what they do.

/// Whether `a` and `b` hold the same bits: their bytes compared by the C
/// library's `memcmp` (the comparisons of a kept state run on every step,
/// over the rail's 922 entries; or-ing the entries' bits took eight
/// instructions an entry, a byte compare a fraction of one), or, below
/// `SHORT` entries (the paper's beam of 2 elements), entry by entry
/// without the call.
#[inline]
pub fn same_bits(a: &[f64], b: &[f64]) -> bool {
    const SHORT: usize = 16;
    if a.len() != b.len() {
        return false;
    }
    if a.len() < SHORT {
        let differ = (a.iter().zip(b)).fold(0u64, |d, (p, q)| d | (p.to_bits() ^ q.to_bits()));
        return differ == 0;
    }
    bytemuck::cast_slice::<f64, u8>(a) == bytemuck::cast_slice::<f64, u8>(b)
}

/// `to ← from` (of one length) by slice copies of at most 2 kB: above
/// about 4 kB glibc's memcpy moves bytes by `rep movsb`, which callgrind
/// counts as one instruction a byte, and the copies would seem to cost
/// several times the loops they replace.
#[inline]
pub fn copy_in_blocks(to: &mut [f64], from: &[f64]) {
    const BLOCK: usize = 256;
    assert_eq!(to.len(), from.len(), "copied vectors' lengths");
    for (to, from) in to.chunks_mut(BLOCK).zip(from.chunks(BLOCK)) {
        to.copy_from_slice(from);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_not_values_decide() {
        let a: Vec<f64> = (0..21).map(|i| i as f64 * 0.5).collect();
        let mut b = a.clone();
        assert!(same_bits(&a, &b));
        assert!(same_bits(&a, &b));
        b[0] = -0.0;
        assert!(!same_bits(&a, &b), "−0 is not +0");
        b[0] = 0.0;
        b[9] = f64::from_bits(b[9].to_bits() + 1);
        assert!(!same_bits(&a, &b), "one ulp in a block");
        assert!(!same_bits(&a, &a[..20]), "another length");
        let mut to = vec![0.0; 600];
        let from: Vec<f64> = (0..600).map(|i| i as f64).collect();
        copy_in_blocks(&mut to, &from);
        assert!(same_bits(&to, &from));
        to[599] = f64::from_bits(to[599].to_bits() ^ 1);
        assert!(
            !same_bits(&to, &from),
            "one ulp in the last entry of a long vector"
        );
    }
}
