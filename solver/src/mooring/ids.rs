//! Typed indices of a mooring line's mesh: nodes and elements, numbered from the fairlead.
//!
//! They live apart from the line model so that both the model and the line errors, which name
//! the node with the largest residual, can use them without depending on each other.

/// Index of a node along a line, 0 at the fairlead.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeId(pub usize);

impl std::fmt::Display for NodeId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// Index of an element along a line, 0 at the fairlead.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ElementId(pub usize);
