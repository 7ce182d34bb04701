//! The compiled *Cages operator: one sparse matrix (rows: points; columns: cage vertices, then
//! Green face DOFs) in f32 CSR, with its transpose for incremental updates, and a rest offset
//! per row. A frame is the Green face terms from the posed cage, then one parallel sparse
//! matrix–vector product plus the offsets: S(posed) + p − S(rest), the displacement form that
//! gives every bound point back at rest whatever its coordinates (docs/math.md).

use glam::{DVec3, Vec3, Vec3A};
use rayon::prelude::*;

use super::green_dofs::GreenDofs;
use super::splice_rows::{CsrRows, splice_rows};
use super::splice_transpose::{Side, Transpose, spliced_transpose};
use super::tables::Row;

/// The compiled operator.
#[derive(Debug, Clone, PartialEq)]
pub struct StarOperator {
    vertex_count: usize,
    green: GreenDofs,
    row_start: Vec<u32>,
    columns: Vec<u32>,
    values: Vec<f32>,
    /// Transpose: for each column, the rows that reference it.
    column_start: Vec<u32>,
    column_rows: Vec<u32>,
    /// For each cage vertex, the Green DOFs whose triangle uses it (what a move of it changes
    /// besides its own column).
    green_of_vertex_start: Vec<u32>,
    green_of_vertex: Vec<u32>,
    /// Per row, p − S(rest) in f32 (zero until [`StarOperator::set_rest_offsets`]): what the
    /// coordinates miss of the point at rest (a harmonic grid's discretisation error, a point
    /// outside its cage following the closest point of it, the weights' f32 rounding).
    rest_offset: Vec<Vec3>,
}

/// CSR lists of the Green DOFs each of `vertex_count` vertices belongs to, in DOF order.
fn green_of_vertex(green: &GreenDofs, vertex_count: usize) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; vertex_count + 1];
    for t in green.triangles() {
        for &v in t {
            if let Some(count) = start.get_mut(v as usize + 1) {
                *count += 1;
            }
        }
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    let mut fill = start.clone();
    let mut dofs = vec![0u32; start.last().copied().unwrap_or(0) as usize];
    for (d, t) in green.triangles().iter().enumerate() {
        for &v in t {
            if let Some(at) = fill.get_mut(v as usize) {
                dofs[*at as usize] = d as u32;
                *at += 1;
            }
        }
    }
    (start, dofs)
}

/// CSR arrays under construction (a splice).
struct Csr {
    row_start: Vec<u32>,
    columns: Vec<u32>,
    values: Vec<f32>,
    rest_offset: Vec<Vec3>,
}

/// Sparse rows (a column or vertex index and an f32 weight per entry) packed into CSR arrays
/// as they come, chunk by chunk (a streamed bind): the operator's rows and the join weights.
#[derive(Default)]
pub(crate) struct RowAppender {
    pub(crate) row_start: Vec<u32>,
    pub(crate) index: Vec<u32>,
    pub(crate) value: Vec<f32>,
}

impl RowAppender {
    /// Reserves room for `factor` × the rows and entries of `rows` more (a bind's first chunk
    /// scaled to all its points): allocated once, where doubling growth would hold up to twice
    /// the arrays at the last copy.
    pub(crate) fn reserve(&mut self, rows: &[Row], factor: f64) {
        let entries: usize = rows.iter().map(Vec::len).sum();
        let entries = (entries as f64 * factor * 1.05) as usize + 16;
        self.row_start
            .reserve_exact((rows.len() as f64 * factor) as usize + 1);
        self.index.reserve_exact(entries);
        self.value.reserve_exact(entries);
    }

    /// Appends `rows`, weights rounded to f32.
    pub(crate) fn push(&mut self, rows: &[Row]) {
        if self.row_start.is_empty() {
            self.row_start.push(0);
        }
        for row in rows {
            for &(c, w) in row {
                self.index.push(c);
                self.value.push(w as f32);
            }
            self.row_start.push(self.index.len() as u32);
        }
    }

    /// The arrays, trimmed to their length (row starts, indices, values).
    pub(crate) fn finish(mut self) -> (Vec<u32>, Vec<u32>, Vec<f32>) {
        if self.row_start.is_empty() {
            self.row_start.push(0);
        }
        self.row_start.shrink_to_fit();
        self.index.shrink_to_fit();
        self.value.shrink_to_fit();
        (self.row_start, self.index, self.value)
    }

    /// The operator over the rows appended (rest offsets zero until set).
    pub(crate) fn into_operator(self, vertex_count: usize, green: GreenDofs) -> StarOperator {
        let (row_start, columns, values) = self.finish();
        let rest_offset = vec![Vec3::ZERO; row_start.len() - 1];
        StarOperator::from_csr(
            vertex_count,
            green,
            Csr {
                row_start,
                columns,
                values,
                rest_offset,
            },
        )
    }
}

impl StarOperator {
    #[cfg(test)]
    pub(crate) fn from_rows(rows: &[Row], vertex_count: usize, green: GreenDofs) -> Self {
        let mut appender = RowAppender::default();
        appender.reserve(rows, 1.0);
        appender.push(rows);
        appender.into_operator(vertex_count, green)
    }

    /// The operator over CSR arrays whose indices are in range (callers check), with the
    /// transpose and the Green lists derived.
    fn from_csr(vertex_count: usize, green: GreenDofs, csr: Csr) -> Self {
        let n_columns = vertex_count + green.len();
        let mut counts = vec![0u32; n_columns + 1];
        for &c in &csr.columns {
            counts[c as usize + 1] += 1;
        }
        for k in 1..counts.len() {
            counts[k] += counts[k - 1];
        }
        let column_start = counts.clone();
        let mut column_rows = vec![0u32; csr.columns.len()];
        let mut fill = counts;
        for (r, range) in csr.row_start.windows(2).enumerate() {
            for &c in &csr.columns[range[0] as usize..range[1] as usize] {
                column_rows[fill[c as usize] as usize] = r as u32;
                fill[c as usize] += 1;
            }
        }
        let transpose = Transpose {
            start: column_start,
            rows: column_rows,
        };
        Self::from_csr_and_transpose(vertex_count, green, csr, transpose)
    }

    /// The operator of `csr` with its transpose, already built.
    fn from_csr_and_transpose(
        vertex_count: usize,
        green: GreenDofs,
        csr: Csr,
        transpose: Transpose,
    ) -> Self {
        let Csr {
            row_start,
            columns,
            values,
            rest_offset,
        } = csr;
        let Transpose {
            start: column_start,
            rows: column_rows,
        } = transpose;
        let (green_of_vertex_start, green_of_vertex) = green_of_vertex(&green, vertex_count);
        Self {
            vertex_count,
            green,
            rest_offset,
            row_start,
            columns,
            values,
            column_start,
            column_rows,
            green_of_vertex_start,
            green_of_vertex,
        }
    }

    /// The rows' columns and values.
    fn csr_rows(&self) -> CsrRows<'_, u32, f32> {
        CsrRows {
            start: &self.row_start,
            a: &self.columns,
            b: &self.values,
        }
    }

    /// This operator with the rows `rows` (increasing, in range) replaced, in order, by the rows
    /// of `part` (with their rest offsets), whose columns `remap` takes to this operator's
    /// numbering extended by the Green DOFs `green` (ours, then the part's new triangles).
    /// Every other row is copied bit for bit, in parallel ([`splice_rows`]).
    pub(crate) fn splice(
        &self,
        rows: &[usize],
        part: &StarOperator,
        remap: impl Fn(u32) -> u32 + Sync,
        green: GreenDofs,
    ) -> Self {
        let (row_start, columns, values, source) =
            splice_rows(&self.csr_rows(), &part.csr_rows(), rows, &remap);
        let rest_offset = source
            .iter()
            .map(|&(from_part, i)| {
                let from = if from_part { part } else { self };
                from.rest_offset[i as usize]
            })
            .collect();
        let out = Csr {
            row_start,
            columns,
            values,
            rest_offset,
        };
        // The transpose from ours, column by column (or whole again if the part's columns do
        // not map one to one).
        let part_to_ours: Vec<u32> = (0..part.dof_count() as u32).map(&remap).collect();
        let transpose = spliced_transpose(
            &Side {
                transpose: (&self.column_start, &self.column_rows),
                row_start: &self.row_start,
                columns: &self.columns,
            },
            rows,
            &Side {
                transpose: (&part.column_start, &part.column_rows),
                row_start: &part.row_start,
                columns: &part.columns,
            },
            &part_to_ours,
            self.vertex_count + green.len(),
        );
        match transpose {
            Some(transpose) => {
                Self::from_csr_and_transpose(self.vertex_count, green, out, transpose)
            }
            None => Self::from_csr(self.vertex_count, green, out),
        }
    }

    /// Sets each row's rest offset so that the rest cage `rest` gives `points` back:
    /// p − S(rest), with S(rest) evaluated by this operator's own f32 product.
    pub(crate) fn set_rest_offsets(&mut self, points: &[DVec3], rest: &[DVec3]) {
        let x = self.dofs(rest, rest);
        self.rest_offset = vec![Vec3::ZERO; self.row_count()];
        let mut at_rest = vec![Vec3::ZERO; self.row_count()];
        self.apply(&x, &mut at_rest);
        self.rest_offset = points
            .iter()
            .zip(&at_rest)
            .map(|(p, s)| (*p - s.as_dvec3()).as_vec3())
            .collect();
    }

    /// Per row, p − S(rest) (added to every product).
    pub fn rest_offsets(&self) -> &[Vec3] {
        &self.rest_offset
    }

    /// Rebuilds an operator from its stored parts (a binding cache), checking every index.
    pub(crate) fn from_parts(
        vertex_count: usize,
        green: GreenDofs,
        row_start: Vec<u32>,
        columns: Vec<u32>,
        values: Vec<f32>,
        rest_offset: Vec<Vec3>,
    ) -> Result<Self, String> {
        let n_columns = (vertex_count + green.len()) as u32;
        let monotone = row_start.first() == Some(&0) && row_start.windows(2).all(|w| w[0] <= w[1]);
        if !monotone
            || row_start.last().map(|&l| l as usize) != Some(columns.len())
            || columns.len() != values.len()
        {
            return Err("inconsistent row structure".into());
        }
        if columns.iter().any(|&c| c >= n_columns) || values.iter().any(|v| !v.is_finite()) {
            return Err("column index or weight out of range".into());
        }
        if green
            .triangles()
            .iter()
            .flatten()
            .any(|&v| v as usize >= vertex_count)
        {
            return Err("Green triangle refers to a missing vertex".into());
        }
        // Within the documented coordinate range (±1e9): a forged offset cannot throw a point
        // anywhere.
        let in_range = |o: &Vec3| o.is_finite() && o.abs().max_element() <= 1e9;
        if rest_offset.len() + 1 != row_start.len() || !rest_offset.iter().all(in_range) {
            return Err("inconsistent rest offsets".into());
        }
        let rebuilt = Self::from_csr(
            vertex_count,
            green,
            Csr {
                row_start,
                columns,
                values,
                rest_offset,
            },
        );
        Ok(rebuilt)
    }

    /// The stored parts: vertex count, row starts, columns, values.
    pub fn parts(&self) -> (usize, &[u32], &[u32], &[f32]) {
        (
            self.vertex_count,
            &self.row_start,
            &self.columns,
            &self.values,
        )
    }

    /// Number of columns (degrees of freedom): cage vertices plus Green face DOFs.
    pub fn dof_count(&self) -> usize {
        self.vertex_count + self.green.len()
    }

    /// Number of rows (bound points).
    pub fn row_count(&self) -> usize {
        self.row_start.len() - 1
    }

    /// Stored non-zeros.
    pub fn nonzeros(&self) -> usize {
        self.values.len()
    }

    /// Bytes of the CSR operator (values, column indices, row starts).
    pub fn byte_size(&self) -> usize {
        self.values.len() * 4 + self.columns.len() * 4 + self.row_start.len() * 4
    }

    /// Bytes of the transpose kept for incremental updates.
    pub fn transpose_byte_size(&self) -> usize {
        (self.column_start.len() + self.column_rows.len()) * 4
    }

    /// The Green face DOFs (oriented triangles).
    pub fn green_dofs(&self) -> &GreenDofs {
        &self.green
    }

    /// Row `r` as (column, weight) pairs.
    pub fn row(&self, r: usize) -> impl Iterator<Item = (u32, f32)> + '_ {
        let (a, b) = (self.row_start[r] as usize, self.row_start[r + 1] as usize);
        self.columns[a..b]
            .iter()
            .copied()
            .zip(self.values[a..b].iter().copied())
    }

    /// The degrees of freedom of a pose: posed vertices, then s_t n'_t per Green DOF.
    pub fn dofs(&self, rest: &[DVec3], posed: &[DVec3]) -> Vec<Vec3> {
        let mut x: Vec<Vec3> = posed.iter().map(|p| p.as_vec3()).collect();
        x.extend(self.green.values(rest, posed).iter().map(|v| v.as_vec3()));
        x
    }

    /// Row `r` times the DOFs, plus its rest offset: four independent SIMD accumulators, so the
    /// sum is bound by loads rather than by the latency of one chain of additions.
    fn apply_row(&self, r: usize, x: &[Vec3A]) -> Vec3 {
        let (a, b) = (self.row_start[r] as usize, self.row_start[r + 1] as usize);
        let (columns, values) = (&self.columns[a..b], &self.values[a..b]);
        let mut acc = [Vec3A::ZERO; 4];
        let (column_blocks, values_blocks) = (columns.chunks_exact(4), values.chunks_exact(4));
        let (column_tail, value_tail) = (column_blocks.remainder(), values_blocks.remainder());
        for (c, w) in column_blocks.zip(values_blocks) {
            acc[0] += x[c[0] as usize] * w[0];
            acc[1] += x[c[1] as usize] * w[1];
            acc[2] += x[c[2] as usize] * w[2];
            acc[3] += x[c[3] as usize] * w[3];
        }
        for (&c, &w) in column_tail.iter().zip(value_tail) {
            acc[0] += x[c as usize] * w;
        }
        let sum: Vec3 = ((acc[0] + acc[1]) + (acc[2] + acc[3])).into();
        sum + self.rest_offset[r]
    }

    /// The DOFs in 16-byte SIMD vectors, checked against the operator's column count.
    fn simd_dofs(&self, x: &[Vec3]) -> Vec<Vec3A> {
        assert!(
            x.len() >= self.dof_count(),
            "operator needs {} DOFs, got {}",
            self.dof_count(),
            x.len()
        );
        x.iter().map(|&v| Vec3A::from(v)).collect()
    }

    /// Every row applied to the DOFs `x` (one parallel sparse product).
    pub fn apply(&self, x: &[Vec3], out: &mut [Vec3]) {
        let x = self.simd_dofs(x);
        out.par_iter_mut()
            .enumerate()
            .with_min_len(1024)
            .for_each(|(r, y)| *y = self.apply_row(r, &x));
    }

    /// The rows that reference any of `moved` cage vertices or Green DOFs (the points a move
    /// can change), sorted.
    pub fn rows_touched(&self, moved_columns: &[u32]) -> Vec<u32> {
        let rows_of = |c: u32| {
            let (a, b) = (
                self.column_start[c as usize] as usize,
                self.column_start[c as usize + 1] as usize,
            );
            &self.column_rows[a..b]
        };
        if let [c] = moved_columns {
            return rows_of(*c).to_vec(); // the transpose lists rows in order
        }
        // Several columns: mark the rows in a bitmap, then read it in order (no sort).
        let mut marked = vec![0u64; self.row_count().div_ceil(64)];
        for &c in moved_columns {
            for &r in rows_of(c) {
                marked[r as usize / 64] |= 1 << (r % 64);
            }
        }
        let mut rows = Vec::new();
        for (w, &bits) in marked.iter().enumerate() {
            let mut bits = bits;
            while bits != 0 {
                rows.push((w * 64) as u32 + bits.trailing_zeros());
                bits &= bits - 1;
            }
        }
        rows
    }

    /// The Green DOFs whose triangle uses one of `moved`, ascending, each once.
    fn green_dofs_of(&self, moved: &[u32]) -> Vec<u32> {
        let mut dofs: Vec<u32> = moved
            .iter()
            .filter_map(|&v| {
                let a = *self.green_of_vertex_start.get(v as usize)? as usize;
                let b = *self.green_of_vertex_start.get(v as usize + 1)? as usize;
                self.green_of_vertex.get(a..b)
            })
            .flatten()
            .copied()
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        dofs
    }

    /// Columns affected when the given cage vertices move: those vertices and every Green DOF
    /// whose triangle uses one of them (ascending after the vertices).
    pub fn columns_of_moved_vertices(&self, moved: &[u32]) -> Vec<u32> {
        let mut columns: Vec<u32> = moved.to_vec();
        columns.extend(
            self.green_dofs_of(moved)
                .into_iter()
                .map(|d| self.vertex_count as u32 + d),
        );
        columns
    }

    /// Brings the DOFs `x` of a pose (from [`StarOperator::dofs`]) up to date after the cage
    /// vertices `moved` took their positions in `posed`: their columns and the Green DOFs of
    /// their triangles, nothing else (equal to calling `dofs` again).
    pub fn update_dofs(&self, rest: &[DVec3], posed: &[DVec3], moved: &[u32], x: &mut [Vec3]) {
        for &v in moved {
            if let (Some(column), Some(p)) = (x.get_mut(v as usize), posed.get(v as usize)) {
                *column = p.as_vec3();
            }
        }
        for d in self.green_dofs_of(moved) {
            if let Some(column) = x.get_mut(self.vertex_count + d as usize) {
                *column = self.green.value(d as usize, rest, posed).as_vec3();
            }
        }
    }

    /// Brings `out` (the product for the DOFs before) up to date for the DOFs `x` after the
    /// cage vertices `moved` changed: only the rows that reference them
    /// ([`StarOperator::rows_touched`], [`StarOperator::apply_rows`]), or every row when the
    /// moved columns hold more than a fifth of the weights (a move of an internal cage over
    /// most of a mesh): finding the rows then costs more than one parallel product
    /// (docs/performance.md, "Design measurements").
    pub fn apply_after_move(&self, moved: &[u32], x: &[Vec3], out: &mut [Vec3]) {
        let columns = self.columns_of_moved_vertices(moved);
        if self.holds_most_weights(&columns) {
            self.apply(x, out);
        } else {
            self.apply_rows(&self.rows_touched(&columns), x, out);
        }
    }

    /// Whether `columns` hold more than a fifth of the weights: then a pass over every row
    /// costs less than finding the rows that reference them through the transpose.
    pub fn holds_most_weights(&self, columns: &[u32]) -> bool {
        let referenced: usize = columns
            .iter()
            .filter_map(|&c| {
                let a = *self.column_start.get(c as usize)?;
                let b = *self.column_start.get(c as usize + 1)?;
                Some((b - a) as usize)
            })
            .sum();
        referenced > self.nonzeros() / 5
    }

    /// Updates only the rows in `rows` (from [`StarOperator::rows_touched`]).
    pub fn apply_rows(&self, rows: &[u32], x: &[Vec3], out: &mut [Vec3]) {
        let x = self.simd_dofs(x);
        // Blocks of rows per task: one task per row cost more than the rows (a move of an
        // internal cage touches a fifth of a large mesh).
        let values: Vec<Vec3> = rows
            .par_iter()
            .with_min_len(1024)
            .map(|&r| self.apply_row(r as usize, &x))
            .collect();
        for (&r, v) in rows.iter().zip(values) {
            out[r as usize] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A splice's transpose, merged column by column from the one before, is the transpose of
    /// the spliced CSR built whole: replacing rows first, last and in between, with rows that
    /// drop columns, gain new ones and reach Green columns the part adds; and where two of the
    /// part's columns map to one of ours, the whole transpose is built instead.
    #[test]
    fn a_spliced_transpose_is_the_transpose_of_the_spliced_rows() {
        let row = |r: u32, width: u32, shift: u32| -> Row {
            (0..width)
                .map(|k| ((r * 7 + k * 5 + shift) % 12, 0.1 + f64::from(k)))
                .collect::<std::collections::BTreeMap<u32, f64>>()
                .into_iter()
                .collect()
        };
        let old_rows: Vec<Row> = (0..40u32).map(|r| row(r, 1 + r % 5, 0)).collect();
        let green = GreenDofs::from_triangles(vec![[0, 1, 2], [3, 4, 5]]);
        let old = StarOperator::from_rows(&old_rows, 10, green);
        let replaced = [0usize, 3, 4, 17, 39];
        // The part: 10 vertex columns and three Green triangles, the first ours, then two new.
        let part_green = GreenDofs::from_triangles(vec![[3, 4, 5], [6, 7, 8], [1, 8, 9]]);
        let part_rows: Vec<Row> = (0..replaced.len() as u32)
            .map(|k| row(k, 2 + k % 4, 3))
            .collect();
        let part = StarOperator::from_rows(&part_rows, 10, part_green);
        let all = GreenDofs::from_triangles(vec![[0, 1, 2], [3, 4, 5], [6, 7, 8], [1, 8, 9]]);
        let part_green_to_ours = [11u32, 12, 13];
        let remap = |c: u32| {
            if c < 10 {
                c
            } else {
                part_green_to_ours[(c - 10) as usize]
            }
        };
        let spliced = old.splice(&replaced, &part, remap, all.clone());
        let (_, row_start, columns, values) = spliced.parts();
        let whole = StarOperator::from_csr(
            10,
            all.clone(),
            Csr {
                row_start: row_start.to_vec(),
                columns: columns.to_vec(),
                values: values.to_vec(),
                rest_offset: spliced.rest_offset.clone(),
            },
        );
        assert_eq!(spliced.column_start, whole.column_start);
        assert_eq!(spliced.column_rows, whole.column_rows);
        assert!(spliced.column_rows.len() > 20);
        // Two part columns onto one of ours: built whole, still right.
        let collapsed = old.splice(&replaced, &part, |c| c.min(11), all);
        let (_, row_start, columns, values) = collapsed.parts();
        let mut csr_rows: Vec<Row> = Vec::new();
        for r in 0..collapsed.row_count() {
            let (a, b) = (row_start[r] as usize, row_start[r + 1] as usize);
            csr_rows.push(
                columns[a..b]
                    .iter()
                    .zip(&values[a..b])
                    .map(|(&c, &v)| (c, f64::from(v)))
                    .collect(),
            );
        }
        assert_eq!(collapsed.row_count(), 40);
        let rows_of_11: Vec<u32> = (0..40u32)
            .filter(|&r| csr_rows[r as usize].iter().any(|(c, _)| *c == 11))
            .collect();
        let (a, b) = (
            collapsed.column_start[11] as usize,
            collapsed.column_start[12] as usize,
        );
        assert_eq!(collapsed.column_rows[a..b], rows_of_11[..]);
    }

    /// After a move, the rows found one by one (few columns) and the full product (columns
    /// holding more than a fifth of the weights) both give what a full product from scratch
    /// gives; rows the move does not reach keep their values.
    #[test]
    fn apply_after_move_matches_a_full_product_on_either_path() {
        let rows: Vec<Row> = (0..500u32)
            .map(|r| {
                (0..9u32)
                    .filter(|c| (r * 13 + c * 7) % 4 < 2)
                    .map(|c| (c, f64::from(1 + (r + c) % 3) * 0.1))
                    .collect()
            })
            .collect();
        let operator = StarOperator::from_rows(&rows, 9, GreenDofs::default());
        let rest: Vec<DVec3> = (0..9).map(|i| DVec3::new(f64::from(i), 0.0, 1.0)).collect();
        for moved in [vec![4u32], vec![0, 1, 2, 3, 4, 5, 6]] {
            let mut out = vec![Vec3::ZERO; operator.row_count()];
            operator.apply(&operator.dofs(&rest, &rest), &mut out);
            let mut posed = rest.clone();
            for &v in &moved {
                posed[v as usize] += DVec3::new(0.5, -1.0, 2.0);
            }
            let x = operator.dofs(&rest, &posed);
            operator.apply_after_move(&moved, &x, &mut out);
            let mut expected = vec![Vec3::ZERO; operator.row_count()];
            operator.apply(&x, &mut expected);
            assert_eq!(out, expected, "moved {moved:?}");
        }
    }

    #[test]
    fn rows_touched_lists_exactly_the_rows_referencing_the_columns_in_order() {
        // 200 rows over 7 columns, each row a pseudo-random subset.
        let rows: Vec<Row> = (0..200u32)
            .map(|r| {
                (0..7u32)
                    .filter(|c| (r * 31 + c * 17) % 5 < 2)
                    .map(|c| (c, 1.0))
                    .collect()
            })
            .collect();
        let operator = StarOperator::from_rows(&rows, 7, GreenDofs::default());
        for moved in [vec![3], vec![0, 6], vec![1, 2, 5], vec![]] {
            let expected: Vec<u32> = (0..200u32)
                .filter(|&r| rows[r as usize].iter().any(|(c, _)| moved.contains(c)))
                .collect();
            assert_eq!(operator.rows_touched(&moved), expected, "columns {moved:?}");
        }
    }

    #[test]
    fn product_matches_a_plain_sum_for_every_row_length() {
        // Rows of 0 to 11 entries exercise the four-wide blocks and every tail length.
        let rows: Vec<Row> = (0..12u32)
            .map(|len| {
                (0..len)
                    .map(|k| ((k * 5 + len) % 13, 0.25 + f64::from(k)))
                    .collect()
            })
            .map(super::super::tables::merge)
            .collect();
        let operator = StarOperator::from_rows(&rows, 13, GreenDofs::default());
        let x: Vec<Vec3> = (0..13)
            .map(|i| Vec3::new(i as f32, 1.0 - i as f32, 0.5 * i as f32))
            .collect();
        let mut out = vec![Vec3::ZERO; rows.len()];
        operator.apply(&x, &mut out);
        for (row, y) in rows.iter().zip(&out) {
            let expected: Vec3 = row.iter().map(|&(c, w)| x[c as usize] * w as f32).sum();
            assert!(
                (*y - expected).length() <= 1e-4 * (1.0 + expected.length()),
                "{y} vs {expected}"
            );
        }
        let touched = operator.rows_touched(&[4]);
        let mut partial = vec![Vec3::ZERO; rows.len()];
        operator.apply_rows(&touched, &x, &mut partial);
        for &r in &touched {
            assert_eq!(partial[r as usize], out[r as usize]);
        }
    }
}
