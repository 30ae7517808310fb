//! Exact partial derivatives a model may provide (FMI 2.0 `fmi2GetDirectionalDerivative`,
//! FMI 3.0 `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative`). A layer maps the
//! master's value references to [`ScalarRef`]s, checks the call and its arguments, and asks
//! the model for `J * seed`; the adjoint `seed^T * J` the layer builds from the same call.

/// One Real scalar of the model: the declaration (its index in
/// [`Model::declarations`](crate::Model::declarations)) and the element of a vector (0 for
/// a scalar), in the declaration's element order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ScalarRef {
    pub declaration: usize,
    pub element: usize,
}

impl ScalarRef {
    pub const fn new(declaration: usize, element: usize) -> Self {
        Self {
            declaration,
            element,
        }
    }
}
