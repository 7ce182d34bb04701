//! The operator's transpose after a splice, from the transpose before it: each column's rows
//! are its kept rows merged with the replacing rows that reference it, column by column and in
//! parallel, instead of a transpose of the whole CSR again (a rest edit's splice spent most of
//! its time there, whatever the number of rows it replaced).

use rayon::prelude::*;

/// A transpose: for each column, the rows that reference it, in increasing order.
pub(super) struct Transpose {
    pub start: Vec<u32>,
    pub rows: Vec<u32>,
}

/// One side of a splice: a transpose, and the columns of each of its rows.
pub(super) struct Side<'a> {
    pub transpose: (&'a [u32], &'a [u32]),
    pub row_start: &'a [u32],
    pub columns: &'a [u32],
}

/// Columns per parallel task of the fill.
const COLUMNS_PER_TASK: usize = 64;

/// The transpose of `old` with its rows `replaced` (increasing) replaced, in order, by the rows
/// of `part`, whose column c is column `part_to_ours[c]` of the result's `column_count`. None
/// when two of the part's columns are one of ours, or a column is out of range (the caller then
/// transposes the whole result).
pub(super) fn spliced_transpose(
    old: &Side,
    replaced: &[usize],
    part: &Side,
    part_to_ours: &[u32],
    column_count: usize,
) -> Option<Transpose> {
    let (old_start, old_rows) = old.transpose;
    let (part_start, part_rows) = part.transpose;
    let old_columns = old_start.len().checked_sub(1)?;
    let row_count = old.row_start.len().checked_sub(1)?;
    if old_columns > column_count || part_start.len() != part_to_ours.len() + 1 {
        return None;
    }
    let mut is_replaced = vec![false; row_count];
    for &r in replaced {
        *is_replaced.get_mut(r)? = true;
    }
    let mut count: Vec<i64> = (0..column_count)
        .map(|c| match (old_start.get(c), old_start.get(c + 1)) {
            (Some(&a), Some(&b)) => i64::from(b - a),
            _ => 0,
        })
        .collect();
    for &r in replaced {
        let (a, b) = (old.row_start[r] as usize, old.row_start[r + 1] as usize);
        for &c in &old.columns[a..b] {
            *count.get_mut(c as usize)? -= 1;
        }
    }
    let mut part_of = vec![u32::MAX; column_count];
    for (p, &ours) in part_to_ours.iter().enumerate() {
        let slot = part_of.get_mut(ours as usize)?;
        if *slot != u32::MAX {
            return None;
        }
        *slot = p as u32;
        count[ours as usize] += i64::from(part_start[p + 1] - part_start[p]);
    }
    let mut start = Vec::with_capacity(column_count + 1);
    start.push(0u32);
    let mut total: u32 = 0;
    for &n in &count {
        total = total.checked_add(u32::try_from(n).ok()?)?;
        start.push(total);
    }
    let mut rows = vec![0u32; total as usize];
    // Blocks of columns over disjoint slices of the output.
    let mut blocks = Vec::with_capacity(column_count.div_ceil(COLUMNS_PER_TASK));
    let mut rest: &mut [u32] = &mut rows;
    for c0 in (0..column_count).step_by(COLUMNS_PER_TASK) {
        let c1 = (c0 + COLUMNS_PER_TASK).min(column_count);
        let (block, tail) = rest.split_at_mut((start[c1] - start[c0]) as usize);
        blocks.push((c0..c1, block));
        rest = tail;
    }
    blocks.into_par_iter().for_each(|(columns, out)| {
        let mut at = 0;
        for c in columns {
            let kept: &[u32] = if c < old_columns {
                &old_rows[old_start[c] as usize..old_start[c + 1] as usize]
            } else {
                &[]
            };
            let new: &[u32] = match part_of[c] {
                u32::MAX => &[],
                p => {
                    &part_rows[part_start[p as usize] as usize..part_start[p as usize + 1] as usize]
                }
            };
            let mut kept = kept
                .iter()
                .copied()
                .filter(|&r| !is_replaced[r as usize])
                .peekable();
            let mut new = new.iter().map(|&k| replaced[k as usize] as u32).peekable();
            loop {
                let next = match (kept.peek(), new.peek()) {
                    (Some(&a), Some(&b)) if a < b => kept.next(),
                    (Some(_), Some(_)) | (None, Some(_)) => new.next(),
                    (Some(_), None) => kept.next(),
                    (None, None) => break,
                };
                if let (Some(r), Some(slot)) = (next, out.get_mut(at)) {
                    *slot = r;
                    at += 1;
                }
            }
        }
    });
    Some(Transpose { start, rows })
}
