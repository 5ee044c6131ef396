//! Warnings (`report.json` → `warnings`, kind `unused_option`) for PETSc options that no PETSc
//! object of the run read. Such an option is a typo, or it belongs to a solver this run's route
//! does not use: each route reads its options under its own prefix,
//!
//! ```text
//!   route                                     reads
//!   linear solve (no contact), condensed     -ksp_…, -pc_…, -mat_…   (the main KSP)
//!     contact solvers (newton, relaxation, …)
//!   contact, newton_full (the default)       -contact_snes_…, -contact_ksp_…, -contact_pc_…
//!   contact, snes_vi / tao                   -contact_snes_… / -contact_tao_…, and the main KSP
//!   dual formulation alone                   -ksp_…, -pc_… (its own main solve)
//!   dual after a primal (--estimate)         -dual_ksp_…, -dual_pc_…
//! ```
//!
//! so the warning says which route left the option unread and which prefix would reach the
//! solver that does that route's linear algebra.
use super::warnings::Warning;

/// What the run solved, as far as the PETSc option prefixes go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OptionRoute {
    /// The contact solver's scene name (`newton_full`, `newton`, …), if the run has contact.
    pub contact_solver: Option<&'static str>,
    /// A primal solve ran.
    pub primal: bool,
    /// A dual solve ran.
    pub dual: bool,
}

/// Options of the main linear solver (no prefix).
fn is_main_solver_option(name: &str) -> bool {
    ["-ksp_", "-pc_", "-mat_", "-sub_"].iter().any(|p| name.starts_with(p))
}

/// One warning per unused option (`-name` or `-name value`, as PETSc lists them).
pub fn unused_option_warnings(unused: &[String], route: OptionRoute) -> Vec<Warning> {
    unused.iter().map(|option| Warning { kind: "unused_option", message: message(option, route) }).collect()
}

fn message(option: &str, route: OptionRoute) -> String {
    let name = option.split_whitespace().next().unwrap_or(option);
    let value = option[name.len()..].trim();
    let with_prefix = |prefix: &str| {
        let renamed = format!("-{prefix}{}", &name[1..]);
        if value.is_empty() {
            renamed
        } else {
            format!("{renamed} {value}")
        }
    };
    let unread = format!("PETSc option {option} was not read");
    if is_main_solver_option(name) {
        if route.primal && route.contact_solver == Some("newton_full") {
            return format!(
                "{unread}: a typo, or an option of the main linear solver, which the contact route newton_full \
                 (the default) does not use: its linear solves are inside the full-space SNES, whose options take \
                 the prefix contact_ ({}; its system is indefinite: MUMPS LU, or GMRES with a suitable \
                 preconditioner); or give --contact-solver newton, whose condensation solves with the main linear \
                 solver",
                with_prefix("contact_")
            );
        }
        if !route.primal && !route.dual {
            return format!("{unread}: this run solved no linear system");
        }
    }
    if let Some(rest) = name.strip_prefix("-dual_") {
        if route.dual && !route.primal {
            return format!(
                "{unread}: a dual-only run reads the options of its solve without the prefix dual_ (-{rest}{}); \
                 dual_ is for the dual solve after a primal one (--estimate)",
                if value.is_empty() { String::new() } else { format!(" {value}") }
            );
        }
        if !route.dual {
            return format!("{unread}: this run has no dual solve (--formulation dual or --estimate)");
        }
    }
    if let Some(rest) = name.strip_prefix("-contact_") {
        match route.contact_solver {
            None => return format!("{unread}: the run has no contact"),
            Some(solver) if route.primal && !["newton_full", "snes_vi", "tao"].contains(&solver) => {
                return format!(
                    "{unread}: the contact solver {solver} solves with the main linear solver (options without \
                     the prefix contact_: -{}); the prefix contact_ is read by newton_full, snes_vi and tao",
                    rest
                );
            }
            _ => {}
        }
    }
    format!("{unread} by any solver of this run (a typo?)")
}

#[cfg(test)]
mod tests {
    use super::*;

    const FULL_SPACE: OptionRoute = OptionRoute { contact_solver: Some("newton_full"), primal: true, dual: false };

    #[test]
    fn main_solver_options_on_the_full_space_route_name_the_contact_prefix() {
        let w = unused_option_warnings(&["-ksp_type cg".into(), "-pc_type icc".into()], FULL_SPACE);
        assert_eq!(w.len(), 2);
        assert_eq!(w[0].kind, "unused_option");
        assert!(w[0].message.contains("newton_full") && w[0].message.contains("-contact_ksp_type cg"), "{w:?}");
        assert!(w[0].message.contains("--contact-solver newton"), "{w:?}");
        assert!(w[1].message.contains("-contact_pc_type icc"), "{w:?}");
    }

    #[test]
    fn a_typo_is_called_one_and_prefixes_name_their_route() {
        let w = unused_option_warnings(&["-ksp_tpye cg".into()], FULL_SPACE.with_contact(Some("newton")));
        assert!(w[0].message.contains("a typo?"), "{w:?}");
        let dual_only = OptionRoute { contact_solver: None, primal: false, dual: true };
        let w = unused_option_warnings(&["-dual_ksp_type cg".into()], dual_only);
        assert!(w[0].message.contains("-ksp_type cg") && w[0].message.contains("dual-only"), "{w:?}");
        let w = unused_option_warnings(&["-contact_ksp_type cg".into()], FULL_SPACE.with_contact(Some("newton")));
        assert!(w[0].message.contains("-ksp_type") && w[0].message.contains("newton_full"), "{w:?}");
        let w = unused_option_warnings(&["-contact_snes_monitor".into()], FULL_SPACE.with_contact(None));
        assert!(w[0].message.contains("no contact"), "{w:?}");
    }

    impl OptionRoute {
        fn with_contact(self, contact_solver: Option<&'static str>) -> Self {
            OptionRoute { contact_solver, ..self }
        }
    }
}
