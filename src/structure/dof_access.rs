//! What a structure whose state is not its mesh's free DOFs (the modal
//! reduction, the rail over the deck) does at a contact: it reads and
//! loads one mesh DOF at a time (`dof_value`, `add_dof_load`), and gathers,
//! dots and scatters an element's shape rows from those, the same way for
//! every such structure.

use nalgebra::DVector;

use crate::beam::Shape;

/// Reading and loading the mesh's free DOFs through a structure's own state.
pub trait DofAccess {
    /// Value on the mesh's free DOF `dof` of the field of state `u`.
    fn dof_value(&self, dof: usize, u: &DVector<f64>) -> f64;

    /// `out += scale` × a unit load on the mesh's free DOF `dof`.
    fn add_dof_load(&self, dof: usize, scale: f64, out: &mut DVector<f64>);

    /// The field on an element's four DOFs `dofs` (0 where held).
    fn gather(&self, dofs: &[Option<usize>; 4], u: &DVector<f64>) -> [f64; 4] {
        dofs.map(|dof| dof.map_or(0.0, |i| self.dof_value(i, u)))
    }

    /// Dot a row of `shape` with the field of `u`.
    fn dot(&self, shape: &Shape, row: &[f64; 4], u: &DVector<f64>) -> f64 {
        let local = self.gather(&shape.dofs, u);
        local.iter().zip(row).map(|(a, b)| a * b).sum()
    }

    /// `dot` of two rows with the element's field gathered once for both.
    fn dot_rows(
        &self,
        shape: &Shape,
        (first, second): (&[f64; 4], &[f64; 4]),
        u: &DVector<f64>,
    ) -> (f64, f64) {
        let local = self.gather(&shape.dofs, u);
        let dot = |row: &[f64; 4]| local.iter().zip(row).map(|(a, b)| a * b).sum();
        (dot(first), dot(second))
    }

    /// Two loads at `shape`, `scale_1 row_1 + scale_2 row_2`: one load per
    /// DOF, not two.
    fn scatter_rows(
        &self,
        shape: &Shape,
        (first, scale_1): (&[f64; 4], f64),
        (second, scale_2): (&[f64; 4], f64),
        out: &mut DVector<f64>,
    ) {
        for (k, dof) in shape.dofs.iter().enumerate() {
            if let Some(i) = *dof {
                self.add_dof_load(i, scale_1 * first[k] + scale_2 * second[k], out);
            }
        }
    }

    /// Add the load `scale * row` at `shape` into `out`.
    fn scatter(&self, shape: &Shape, row: &[f64; 4], scale: f64, out: &mut DVector<f64>) {
        for (dof, r) in shape.dofs.iter().zip(row) {
            if let Some(i) = *dof {
                self.add_dof_load(i, scale * r, out);
            }
        }
    }
}
