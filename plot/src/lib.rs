//! # plot — TC paths drawn as SVG
//!
//! An NC program ([`nc_steps`] of an NC run) or a trace ([`trace_steps`])
//! is run on a fresh emulator with `EXEC` stepped cycle by cycle
//! ([`collect_paths`]), and [`render`] draws the programmed contour, the
//! corrected tool-centre path and the executed path (OTC offset included)
//! in the plane of the path's arcs, else X-Y, or X-Z or Y-Z for a path
//! that moves only there. [`Plot`] draws paths in a plane; it also makes
//! the pictures of the docs.

mod path_plot;
mod picture;

pub use path_plot::{
    collect_paths, collect_paths_with, nc_steps, render, trace_steps, Paths, Piece, PlotStep,
    MAX_EXECUTED_POINTS, MAX_STEPPED_CYCLES,
};
pub use picture::{Plot, Series, Stroke};
