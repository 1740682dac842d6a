//! Import cycles of a module graph: the strongly connected components
//! (Tarjan's algorithm), and in each component with more than one module
//! a list of cycles that passes every edge of the component at least once
//! (for each edge `a -> b`: `a -> b`, then the shortest way back to `a`).

use std::collections::{BTreeSet, VecDeque};

use crate::graph::ModuleGraph;
use crate::workspace::shown;

/// Tarjan's strongly connected components of the graph `adj` (node `v`
/// has edges to `adj[v]`).
pub fn components(adj: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let n = adj.len();
    let mut t = Tarjan {
        adj,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        found: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            t.connect(v);
        }
    }
    t.found
}

/// The state of one run of Tarjan's algorithm.
struct Tarjan<'a> {
    adj: &'a [Vec<usize>],
    index: Vec<Option<usize>>,
    low: Vec<usize>,
    on_stack: Vec<bool>,
    stack: Vec<usize>,
    next: usize,
    found: Vec<Vec<usize>>,
}

impl Tarjan<'_> {
    /// Visits `v` and everything reachable from it not yet visited.
    fn connect(&mut self, v: usize) {
        self.index[v] = Some(self.next);
        self.low[v] = self.next;
        self.next += 1;
        self.stack.push(v);
        self.on_stack[v] = true;
        let adj = self.adj;
        for &w in &adj[v] {
            match self.index[w] {
                None => {
                    self.connect(w);
                    self.low[v] = self.low[v].min(self.low[w]);
                }
                Some(iw) if self.on_stack[w] => self.low[v] = self.low[v].min(iw),
                Some(_) => {}
            }
        }
        if self.index[v] == Some(self.low[v]) {
            let mut component = Vec::new();
            while let Some(w) = self.stack.pop() {
                self.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            component.sort_unstable();
            self.found.push(component);
        }
    }
}

/// Cycles covering every edge inside every component of more than one
/// node; each starts and ends at its smallest node, without repeats.
pub fn cycles(adj: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut out = BTreeSet::new();
    for component in components(adj).into_iter().filter(|c| c.len() > 1) {
        let inside: BTreeSet<usize> = component.iter().copied().collect();
        for &a in &component {
            for &b in adj[a].iter().filter(|b| inside.contains(b)) {
                if let Some(back) = shortest_path(adj, &inside, b, a) {
                    let mut cycle = vec![a];
                    cycle.extend(back);
                    out.insert(rotated(cycle));
                }
            }
        }
    }
    out.into_iter().collect()
}

/// The shortest path `from .. to` (both included) through `inside`.
fn shortest_path(
    adj: &[Vec<usize>],
    inside: &BTreeSet<usize>,
    from: usize,
    to: usize,
) -> Option<Vec<usize>> {
    let mut came_from = vec![None; adj.len()];
    let mut queue = VecDeque::from([from]);
    came_from[from] = Some(from);
    while let Some(v) = queue.pop_front() {
        if v == to {
            let mut path = vec![to];
            let mut at = to;
            while at != from {
                at = came_from[at]?;
                path.push(at);
            }
            path.reverse();
            return Some(path);
        }
        for &w in adj[v].iter().filter(|w| inside.contains(w)) {
            if came_from[w].is_none() {
                came_from[w] = Some(v);
                queue.push_back(w);
            }
        }
    }
    None
}

/// `cycle` (first node repeated at the end) started at its smallest node.
fn rotated(mut cycle: Vec<usize>) -> Vec<usize> {
    cycle.pop();
    let first = (0..cycle.len()).min_by_key(|&i| cycle[i]).unwrap_or(0);
    cycle.rotate_left(first);
    cycle.push(cycle[0]);
    cycle
}

/// `crate: a -> b -> a`, then one line per edge with the place that makes
/// it.
pub fn describe(crate_name: &str, graph: &ModuleGraph, cycle: &[usize]) -> String {
    let names: Vec<&str> = cycle.iter().map(|&m| graph.names[m].as_str()).collect();
    let mut text = format!("{crate_name}: {}", names.join(" -> "));
    for pair in cycle.windows(2) {
        if let Some(at) = graph.edges.get(&(pair[0], pair[1])) {
            text += &format!(
                "\n    {} -> {}: {}:{}",
                graph.names[pair[0]],
                graph.names[pair[1]],
                shown(&at.file),
                at.line
            );
        }
    }
    text
}
