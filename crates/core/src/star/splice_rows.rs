//! Rows of a CSR list replaced by another list's rows: the row starts from the rows' lengths,
//! then every row copied in parallel, block by block, into its final place. (Appending slice
//! after slice on one thread was a fifth of a small rest edit on the creature, most of it
//! first touches of the new arrays' pages.)

use rayon::prelude::*;

/// Rows per parallel task of the fill.
const ROWS_PER_TASK: usize = 1024;

/// A CSR list: the start of each row (rows + 1) over two parallel arrays.
pub(super) struct CsrRows<'a, A, B> {
    pub start: &'a [u32],
    pub a: &'a [A],
    pub b: &'a [B],
}

impl<A, B> CsrRows<'_, A, B> {
    fn row(&self, r: usize) -> std::ops::Range<usize> {
        self.start[r] as usize..self.start[r + 1] as usize
    }
}

/// `ours` with its rows `replaced` (increasing, in range) replaced, in order, by the rows of
/// `part`, whose first array's entries go through `map_part` (a column renumbering). Returns
/// the row starts, the two arrays, and per output row whether it came from `part` and the
/// index of the row it copies.
#[allow(clippy::type_complexity)]
pub(super) fn splice_rows<A, B>(
    ours: &CsrRows<A, B>,
    part: &CsrRows<A, B>,
    replaced: &[usize],
    map_part: impl Fn(A) -> A + Sync,
) -> (Vec<u32>, Vec<A>, Vec<B>, Vec<(bool, u32)>)
where
    A: Copy + Default + Send + Sync,
    B: Copy + Default + Send + Sync,
{
    let count = ours.start.len().saturating_sub(1);
    let mut source = Vec::with_capacity(count);
    let mut next = replaced.iter().enumerate().peekable();
    for r in 0..count {
        match next.peek() {
            Some(&(k, &at)) if at == r => {
                source.push((true, k as u32));
                next.next();
            }
            _ => source.push((false, r as u32)),
        }
    }
    let length = |&(from_part, i): &(bool, u32)| {
        let side = if from_part { part } else { ours };
        side.row(i as usize).len() as u32
    };
    let mut start = Vec::with_capacity(count + 1);
    start.push(0u32);
    let mut total = 0u32;
    for s in &source {
        total += length(s);
        start.push(total);
    }
    let mut a = vec![A::default(); total as usize];
    let mut b = vec![B::default(); total as usize];
    // Blocks of rows over disjoint slices of the output.
    let mut blocks = Vec::with_capacity(count.div_ceil(ROWS_PER_TASK));
    let (mut rest_a, mut rest_b): (&mut [A], &mut [B]) = (&mut a, &mut b);
    for r0 in (0..count).step_by(ROWS_PER_TASK) {
        let r1 = (r0 + ROWS_PER_TASK).min(count);
        let len = (start[r1] - start[r0]) as usize;
        let (block_a, tail_a) = rest_a.split_at_mut(len);
        let (block_b, tail_b) = rest_b.split_at_mut(len);
        blocks.push((&source[r0..r1], block_a, block_b));
        rest_a = tail_a;
        rest_b = tail_b;
    }
    blocks.into_par_iter().for_each(|(rows, out_a, out_b)| {
        let mut at = 0;
        for &(from_part, i) in rows {
            let side = if from_part { part } else { ours };
            let range = side.row(i as usize);
            let n = range.len();
            let (to_a, to_b) = (&mut out_a[at..at + n], &mut out_b[at..at + n]);
            if from_part {
                for (to, &x) in to_a.iter_mut().zip(&side.a[range.clone()]) {
                    *to = map_part(x);
                }
            } else {
                to_a.copy_from_slice(&side.a[range.clone()]);
            }
            to_b.copy_from_slice(&side.b[range]);
            at += n;
        }
    });
    (start, a, b, source)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parallel splice gives what appending the kept and replacing rows one after the other
    /// gives, over more rows than one task holds, with empty rows and a renumbered part.
    #[test]
    fn splicing_in_parallel_equals_appending_row_by_row() {
        let rows = 3 * ROWS_PER_TASK + 17;
        let row = |seed: usize, r: usize| -> Vec<(u32, f32)> {
            (0..(r * 7 + seed) % 5)
                .map(|k| ((r + k) as u32, (r * 10 + k + seed) as f32))
                .collect()
        };
        let pack = |rows: Vec<Vec<(u32, f32)>>| {
            let mut start = vec![0u32];
            let (mut a, mut b) = (Vec::new(), Vec::new());
            for r in rows {
                for (x, y) in r {
                    a.push(x);
                    b.push(y);
                }
                start.push(a.len() as u32);
            }
            (start, a, b)
        };
        let ours_rows: Vec<_> = (0..rows).map(|r| row(0, r)).collect();
        let replaced: Vec<usize> = (0..rows).filter(|r| r % 3 == 1 || *r == rows - 1).collect();
        let part_rows: Vec<_> = (0..replaced.len()).map(|k| row(1, k)).collect();
        let expected: Vec<Vec<(u32, f32)>> = {
            let mut next = 0;
            (0..rows)
                .map(|r| {
                    if replaced.get(next) == Some(&r) {
                        next += 1;
                        part_rows[next - 1]
                            .iter()
                            .map(|&(x, y)| (x + 1000, y))
                            .collect()
                    } else {
                        ours_rows[r].clone()
                    }
                })
                .collect()
        };
        let (os, oa, ob) = pack(ours_rows);
        let (ps, pa, pb) = pack(part_rows);
        let ours = CsrRows {
            start: &os,
            a: &oa,
            b: &ob,
        };
        let part = CsrRows {
            start: &ps,
            a: &pa,
            b: &pb,
        };
        let (start, a, b, source) = splice_rows(&ours, &part, &replaced, |x| x + 1000);
        assert_eq!((start, a, b), pack(expected));
        assert_eq!(
            source.iter().filter(|(from_part, _)| *from_part).count(),
            replaced.len()
        );
    }
}
