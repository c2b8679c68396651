//! A scheme of each kind: [`SchemeKind::build`], the one place that knows every scheme.

use crate::{
    CentralDifference, Chin, ForestRuth, Integrator, Omf30, Omf32, Pc3, Pc4, Pc5, SchemeKind,
};

impl SchemeKind {
    /// A new integrator of this kind for `n` DOFs (buffers allocated once, here).
    pub fn build(self, n: usize) -> Box<dyn Integrator> {
        match self {
            SchemeKind::CentralDifference => Box::new(CentralDifference::new(n)),
            SchemeKind::Pc3 => Box::new(Pc3::new(n)),
            SchemeKind::Pc4 => Box::new(Pc4::new(n)),
            SchemeKind::Pc5 => Box::new(Pc5::new(n)),
            SchemeKind::Chin => Box::new(Chin::new(n)),
            SchemeKind::Omf30 => Box::new(Omf30::new(n)),
            SchemeKind::Omf32 => Box::new(Omf32::new(n)),
            SchemeKind::ForestRuth => Box::new(ForestRuth::new(n)),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::SchemeKind;

    #[test]
    fn every_kind_builds_a_scheme_of_that_kind() {
        for k in SchemeKind::ALL {
            assert_eq!(k.build(3).kind(), k);
        }
    }
}
