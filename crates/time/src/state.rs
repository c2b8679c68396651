//! The state a scheme advances: time, positions and velocities as flat DOF arrays.

/// Time, positions and velocities of a second-order system, as flat degree-of-freedom arrays.
///
/// In 2D, DOF `2i` is the x component of node `i` and DOF `2i + 1` its y component;
/// [`State::x_nodes`] and [`State::v_nodes`] give the `[[f64; 2]]` node views.
/// Velocities are always the velocities *at time `t`* (synchronised with the positions),
/// whatever the scheme.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time (s).
    pub t: f64,
    /// Positions, one entry per DOF.
    pub x: Vec<f64>,
    /// Velocities at time `t`, one entry per DOF.
    pub v: Vec<f64>,
}

impl State {
    /// A state at time `t` from positions and velocities of the same length.
    ///
    /// # Panics
    /// If `x` and `v` differ in length (a programming error, not user input).
    pub fn new(t: f64, x: Vec<f64>, v: Vec<f64>) -> Self {
        assert_eq!(
            x.len(),
            v.len(),
            "positions and velocities differ in length"
        );
        Self { t, x, v }
    }

    /// A state from 2D node arrays (DOF `2i` is x of node `i`, `2i + 1` its y).
    ///
    /// # Panics
    /// If `x` and `v` hold different numbers of nodes.
    pub fn from_nodes(t: f64, x: &[[f64; 2]], v: &[[f64; 2]]) -> Self {
        Self::new(t, x.as_flattened().to_vec(), v.as_flattened().to_vec())
    }

    /// `n` DOFs at rest at the origin, time 0.
    pub fn zeros(n: usize) -> Self {
        Self {
            t: 0.0,
            x: vec![0.0; n],
            v: vec![0.0; n],
        }
    }

    /// Number of degrees of freedom.
    pub fn n_dofs(&self) -> usize {
        self.x.len()
    }

    /// Positions viewed as 2D nodes (a trailing odd DOF, if any, is left out).
    pub fn x_nodes(&self) -> &[[f64; 2]] {
        self.x.as_chunks::<2>().0
    }

    /// Positions viewed as mutable 2D nodes.
    pub fn x_nodes_mut(&mut self) -> &mut [[f64; 2]] {
        self.x.as_chunks_mut::<2>().0
    }

    /// Velocities viewed as 2D nodes.
    pub fn v_nodes(&self) -> &[[f64; 2]] {
        self.v.as_chunks::<2>().0
    }

    /// Velocities viewed as mutable 2D nodes.
    pub fn v_nodes_mut(&mut self) -> &mut [[f64; 2]] {
        self.v.as_chunks_mut::<2>().0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_views_interleave_x_and_y() {
        let mut s = State::new(0.0, vec![1.0, 2.0, 3.0, 4.0], vec![0.0; 4]);
        assert_eq!(s.x_nodes(), &[[1.0, 2.0], [3.0, 4.0]]);
        s.v_nodes_mut()[1][0] = 5.0;
        assert_eq!(s.v[2], 5.0);
        let r = State::from_nodes(1.0, s.x_nodes(), s.v_nodes());
        assert_eq!(r.x, s.x);
        assert_eq!(r.v, s.v);
    }
}
