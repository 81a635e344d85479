//! What the command's charts decide, as Python data for `cushion.plot`: figure 3's layout
//! (`cushion_sweep::figure::FIGURE3`), so that `cushion.plot.run` draws what the command's SVG
//! draws, and how each quantity is named (`cushion_sweep::quantities`).

use cushion_sweep::figure::{FIGURE3, FIGURE3_MARKS};
use cushion_sweep::quantities::{Quantity, AXES, METRICS};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// `FIGURE3`: one dict per panel, top to bottom (title, quantity, symbol, unit, factor from SI,
/// curves as dicts of column, name, symbol and colour, and the note shown when nothing is
/// drawn).
pub fn panels(py: Python<'_>) -> PyResult<Bound<'_, PyTuple>> {
    let mut out = Vec::with_capacity(FIGURE3.len());
    for spec in FIGURE3 {
        let curves = spec
            .curves
            .iter()
            .map(|c| {
                let d = PyDict::new(py);
                d.set_item("column", c.column)?;
                d.set_item("name", c.name)?;
                d.set_item("symbol", c.symbol)?;
                d.set_item("color", c.color)?;
                Ok(d)
            })
            .collect::<PyResult<Vec<_>>>()?;
        let d = PyDict::new(py);
        d.set_item("title", spec.title)?;
        d.set_item("quantity", spec.quantity)?;
        d.set_item("symbol", spec.symbol)?;
        d.set_item("unit", spec.unit)?;
        d.set_item("factor", spec.factor)?;
        d.set_item("curves", PyTuple::new(py, curves)?)?;
        d.set_item("absent", spec.absent)?;
        out.push(d);
    }
    PyTuple::new(py, out)
}

/// `FIGURE3_MARKS`: the dashed event lines, as dicts of the summary's field, label and colour.
pub fn marks(py: Python<'_>) -> PyResult<Bound<'_, PyTuple>> {
    let out = FIGURE3_MARKS
        .iter()
        .map(|m| {
            let d = PyDict::new(py);
            d.set_item("field", m.field)?;
            d.set_item("label", m.label)?;
            d.set_item("color", m.color)?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyTuple::new(py, out)
}

/// `QUANTITIES`: how the charts show each summary metric and scene key, as dicts of key, kind
/// (`"metric"` or `"axis"`), name, unit and factor from SI.
pub fn quantities(py: Python<'_>) -> PyResult<Bound<'_, PyTuple>> {
    let kinds = METRICS
        .iter()
        .map(|q| ("metric", q))
        .chain(AXES.iter().map(|q| ("axis", q)));
    let out = kinds
        .map(|(kind, q): (&str, &Quantity)| {
            let d = PyDict::new(py);
            d.set_item("key", q.key)?;
            d.set_item("kind", kind)?;
            d.set_item("name", q.name)?;
            d.set_item("unit", q.unit)?;
            d.set_item("factor", q.factor)?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyTuple::new(py, out)
}
