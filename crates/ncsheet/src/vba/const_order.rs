//! The project's module-level constants in the order VBA compiles them: each after the
//! constants its value reads, whatever module or line declares them, so `Private Const
//! TWO_PI = 2 * PI` in Module1 reads Module2's `Public Const PI` declared after it.
//! [MS-VBAL] 5.2.3.2 "Const Declarations": a constant's value is a constant expression
//! (5.6.16.2), whose simple names are constants found as any simple name (5.6.10); 5.2.4
//! (static semantics of module declarations) and VBA's compile error "Circular dependencies
//! between modules": a constant may not depend on itself, directly or through others.
//!
//! The order is found in time proportional to the constants and the names they read (one
//! hash probe a name, each constant visited once), so 100,000 constants stay fast.

use std::collections::HashMap;
use std::rc::Rc;

use super::ast::Ty;
use super::parser::Build;
use super::resolve::lower_bare;
use crate::formula::ast::{Expr, ExprKind};

/// One module-level constant (a `Const` item or an Enum member) of the module `part`.
pub(super) struct ModuleConst {
    pub(super) part: usize,
    pub(super) name: Rc<str>,
    pub(super) ty: Option<Ty>,
    pub(super) value: Expr,
}

/// Indexes of the nodes of a graph, each after every node it depends on (`deps[i]`: the
/// nodes `i` reads); nodes that depend on none of the others keep their relative order.
/// A cycle is `Err` with its nodes, each depending on the next and the last on the first.
pub(super) fn dependency_order(deps: &[Vec<usize>]) -> Result<Vec<usize>, Vec<usize>> {
    #[derive(Clone, Copy, PartialEq)]
    enum State {
        New,
        Open,
        Done,
    }
    let mut state = vec![State::New; deps.len()];
    let mut order = Vec::with_capacity(deps.len());
    // Depth first without recursion: a chain of 100,000 constants would overflow the stack.
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for root in 0..deps.len() {
        if state[root] != State::New {
            continue;
        }
        state[root] = State::Open;
        stack.push((root, 0));
        while let Some(&(node, next)) = stack.last() {
            let Some(&dep) = deps[node].get(next) else {
                state[node] = State::Done;
                order.push(node);
                stack.pop();
                continue;
            };
            stack.last_mut().expect("the node being visited").1 += 1;
            match state[dep] {
                State::New => {
                    state[dep] = State::Open;
                    stack.push((dep, 0));
                }
                State::Open => {
                    let from = stack.iter().position(|&(n, _)| n == dep).expect("an open node is on the stack");
                    return Err(stack[from..].iter().map(|&(n, _)| n).collect());
                }
                State::Done => {}
            }
        }
    }
    Ok(order)
}

impl Build<'_> {
    /// For each constant, the others its value reads (by their index in `consts`).
    pub(super) fn const_dependencies(&self, consts: &[ModuleConst]) -> Vec<Vec<usize>> {
        let mut index: HashMap<(usize, String), usize> = HashMap::with_capacity(consts.len());
        for (i, c) in consts.iter().enumerate() {
            index.entry((c.part, lower_bare(&c.name))).or_insert(i);
        }
        let reads = |c: &ModuleConst| {
            self.current_part.set(c.part);
            let mut deps = Vec::new();
            c.value.visit(&mut |e| {
                if let ExprKind::Name(name) = &e.kind {
                    deps.extend(self.constant_named(name).and_then(|key| index.get(&key)));
                }
            });
            deps
        };
        consts.iter().map(reads).collect()
    }

    /// The module and lower-case name of the module-level name `name` that the module
    /// being built reads ([MS-VBAL] 5.6.10): `Module2.PI` is Module2's; a plain name its own
    /// module's, else the one other module's that declares it Public.
    fn constant_named(&self, name: &str) -> Option<(usize, String)> {
        if let Some((module, bare)) = name.split_once('.') {
            let part = self.parts.iter().position(|p| p.name.eq_ignore_ascii_case(module) && !p.class)?;
            return Some((part, lower_bare(bare)));
        }
        let lower = lower_bare(name);
        let part = self.current_part.get();
        let own = self.globals.borrow().get(&lower).is_some_and(|owners| owners.iter().any(|o| o.part == part));
        if own {
            return Some((part, lower));
        }
        match self.public_owners(&lower).as_slice() {
            [one] => Some((*one, lower)),
            _ => None,
        }
    }

    /// VBA's compile error for constants computed from themselves, naming each with its
    /// module: `A (Module1) needs B (Module2), which needs A`.
    pub(super) fn circular_constants(&self, consts: &[ModuleConst], cycle: &[usize]) -> String {
        // A module run alone has no parts: its constants need no module's name.
        let named = |i: usize| match self.parts.get(consts[i].part) {
            Some(module) => format!("{} ({})", consts[i].name, module.name),
            None => consts[i].name.to_string(),
        };
        let mut chain = named(cycle[0]);
        for (k, &i) in cycle.iter().enumerate().skip(1) {
            chain.push_str(if k == 1 { " needs " } else { ", which needs " });
            chain.push_str(&named(i));
        }
        let back = match cycle.len() {
            1 => " needs itself".to_string(),
            _ => format!(", which needs {}", consts[cycle[0]].name),
        };
        format!("Circular dependencies between modules: the constant {chain}{back}; a constant cannot be computed from itself")
    }
}

#[cfg(test)]
mod tests {
    use super::dependency_order;

    #[test]
    fn each_node_comes_after_the_ones_it_reads() {
        // 0 reads 2, 2 reads 1: 1, 2, 0; 3 reads nothing and stays last.
        assert_eq!(dependency_order(&[vec![2], vec![], vec![1], vec![]]), Ok(vec![1, 2, 0, 3]));
    }

    #[test]
    fn a_cycle_is_named_with_its_nodes() {
        assert_eq!(dependency_order(&[vec![], vec![2], vec![1]]), Err(vec![1, 2]));
        assert_eq!(dependency_order(&[vec![0]]), Err(vec![0]));
    }

    #[test]
    fn a_long_chain_needs_no_deep_stack() {
        let n = 200_000;
        let deps: Vec<Vec<usize>> = (0..n).map(|i| if i + 1 < n { vec![i + 1] } else { vec![] }).collect();
        let order = dependency_order(&deps).unwrap();
        assert_eq!(order.first(), Some(&(n - 1)));
        assert_eq!(order.last(), Some(&0));
    }
}
