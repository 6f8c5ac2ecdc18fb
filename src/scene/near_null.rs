//! The near-null space a scene gives (`"near_null_space"` + `"block_size"`, or `"nodes"`):
//! read and checked against K's size, each error naming the field.

use super::{bare_message, matrix_market, Expecting, Num};
use crate::error::{Error, Result};
use crate::system::NearNull;
use serde::Deserialize;
use std::path::Path;

/// `"near_null_space": {"matrix_market": "B.mtx"}`: B, N×k; with `"slots": [s_0, …]` (one
/// increasing slot per DOF, [`NearNull::with_slots`]) B has one row per slot instead.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawNearNull {
    pub(super) matrix_market: String,
    #[serde(default)]
    pub(super) slots: Option<Vec<usize>>,
}

/// `"nodes": {"coordinates": [[x, y(, z)], ...], "dofs_per_node": d}`, optionally with
/// `"cells": [[n0, n1, …], …]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawNodes {
    pub(super) coordinates: Vec<Vec<Num>>,
    pub(super) dofs_per_node: usize,
    #[serde(default)]
    pub(super) cells: Option<Vec<Vec<usize>>>,
}

impl Expecting for RawNearNull {
    const EXPECTING: &'static str =
        r#"an object {"matrix_market": "B.mtx"} (optionally with "slots": [s_0, ...])"#;
}

impl Expecting for RawNodes {
    const EXPECTING: &'static str = r#"an object {"coordinates": [[x, y], ...], "dofs_per_node": d} (optionally with "cells": [[n0, n1, ...], ...])"#;
}

/// The near-null space a scene gives: B from its file with `block_size` (default 1), or the
/// rigid-body modes of `nodes` (B given and `nodes` too: B wins, `nodes` then only says the
/// block size where `block_size` is absent).
pub(super) fn parse(
    file: Option<RawNearNull>,
    block_size: Option<usize>,
    nodes: Option<&Nodes>,
    n: usize,
    base_dir: &Path,
    at: &dyn Fn(&str, String) -> Error,
) -> Result<Option<NearNull>> {
    let nodes = nodes.map(|n| (n.coordinates.clone(), n.dofs_per_node));
    match file {
        Some(RawNearNull {
            matrix_market: rel,
            slots,
        }) => {
            if rel.trim().is_empty() {
                return Err(at(
                    "near_null_space.matrix_market",
                    "empty file path".into(),
                ));
            }
            let (rows, cols, entries) =
                matrix_market::read_matrix_market_entries(&base_dir.join(&rel))
                    .map_err(|e| at("near_null_space.matrix_market", e.to_string()))?;
            if let Some(s) = slots.as_ref().filter(|s| s.len() != n) {
                return Err(at(
                    "near_null_space.slots",
                    format!(
                        "{} slots, but K has N = {n} DOFs (one slot per DOF)",
                        s.len()
                    ),
                ));
            }
            if slots.is_none() && rows != n {
                return Err(at(
                    "near_null_space.matrix_market",
                    format!("B has {rows} rows, but K has N = {n} DOFs (B is N × k)"),
                ));
            }
            let mut b = vec![0.0; rows * cols];
            for (r, c, v) in entries {
                b[c * rows + r] += v;
            }
            let bs = block_size.or(nodes.as_ref().map(|(_, d)| *d)).unwrap_or(1);
            let nn = NearNull::new(rows, bs, cols, b)
                .map_err(|e| at("near_null_space", bare_message(e)))?;
            match slots {
                Some(s) => nn
                    .with_slots(s)
                    .map(Some)
                    .map_err(|e| at("near_null_space.slots", bare_message(e))),
                None => Ok(Some(nn)),
            }
        }
        None => match nodes {
            // One DOF per node (a scalar field): the default near-null space, B = ones.
            Some((_, 1)) if block_size.is_none_or(|b| b == 1) => Ok(None),
            Some((coords, d)) => {
                if let Some(bs) = block_size.filter(|&bs| bs != d) {
                    return Err(at(
                        "block_size",
                        format!("{bs} differs from nodes.dofs_per_node = {d}"),
                    ));
                }
                NearNull::rigid_body_modes(&coords, d)
                    .map(Some)
                    .map_err(|e| at("nodes", bare_message(e)))
            }
            None => match block_size {
                Some(_) => Err(at(
                    "block_size",
                    "given without \"near_null_space\" or \"nodes\" (nothing to build B from)"
                        .into(),
                )),
                None => Ok(None),
            },
        },
    }
}

/// The nodes a scene may carry (`"nodes"`): coordinates (2 or 3 per node), the DOFs per node
/// (node i owns DOFs `i·d … i·d + d − 1`) and, optionally, the cells (node lists: the VTK
/// output draws them; without cells, one vertex per node).
#[derive(Clone, Debug, PartialEq)]
pub struct Nodes {
    /// Node coordinates, each of length 2 or 3 (one length for all).
    pub coordinates: Vec<Vec<f64>>,
    /// DOFs per node, consecutive.
    pub dofs_per_node: usize,
    /// Cells as node indices (1 to 8 nodes each); empty when the scene gives none.
    pub cells: Vec<Vec<usize>>,
}

/// `"nodes"` checked: `nodes × dofs_per_node = N`, one coordinate length (2 or 3), finite
/// coordinates, cells of 1 to 8 nodes in range.
pub(super) fn nodes(r: RawNodes, n: usize) -> std::result::Result<Nodes, String> {
    let coordinates: Vec<Vec<f64>> = r
        .coordinates
        .into_iter()
        .map(|c| c.into_iter().map(|Num(x)| x).collect())
        .collect();
    let count = coordinates.len();
    if r.dofs_per_node == 0 || count * r.dofs_per_node != n {
        return Err(format!(
            "{count} nodes × {} DOFs per node = {}, but K has N = {n} DOFs",
            r.dofs_per_node,
            count * r.dofs_per_node
        ));
    }
    let dim = coordinates.first().map_or(2, Vec::len);
    if let Some(i) = coordinates
        .iter()
        .position(|c| c.len() != dim || !(2..=3).contains(&c.len()))
    {
        return Err(format!(
            "coordinates of node {i}: {} values (every node 2, or every node 3)",
            coordinates[i].len()
        ));
    }
    if let Some(i) = coordinates
        .iter()
        .position(|c| !c.iter().all(|x| x.is_finite()))
    {
        return Err(format!("coordinates of node {i}: not finite"));
    }
    let cells = r.cells.unwrap_or_default();
    for (c, cell) in cells.iter().enumerate() {
        if !(1..=8).contains(&cell.len()) {
            return Err(format!("cells[{c}] has {} nodes (1 to 8)", cell.len()));
        }
        if let Some(&k) = cell.iter().find(|&&k| k >= count) {
            return Err(format!(
                "cells[{c}] names node {k}, but there are {count} nodes (0-based)"
            ));
        }
    }
    Ok(Nodes {
        coordinates,
        dofs_per_node: r.dofs_per_node,
        cells,
    })
}
