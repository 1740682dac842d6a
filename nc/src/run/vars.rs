//! Parameters and variables: R and P parameters and `V.P.`/`V.L.`
//! variables kept by the interpreter, `V.G.` variables read from (and
//! `V.G.WZ_AKT.R`, also named `V.G.WZR`, written to) the controller's
//! objects.

use tc_request::{Reply, Request};
use uoi::{ObjectAddress, Value, ValueType};

use super::eval::{eval, Vars};
use super::objects;
use super::{unexpected, Interpreter, RunErrorKind};
use crate::expr::Segment;
use crate::Var;

impl Interpreter<'_> {
    /// `NAME.NAME[i]` of a variable path, indices evaluated.
    fn path_key(&mut self, path: &[Segment]) -> Result<String, RunErrorKind> {
        let mut parts = Vec::with_capacity(path.len());
        for seg in path {
            let mut part = seg.name.to_ascii_uppercase();
            if let Some(index) = &seg.index {
                let i = eval(index, self)?;
                part.push_str(&format!("[{i}]"));
            }
            parts.push(part);
        }
        Ok(parts.join("."))
    }

    /// The object behind a `V.G.` variable and its type.
    fn global_object(key: &str) -> Option<(ObjectAddress, ValueType)> {
        use ValueType::{F64, I32};
        Some(match key {
            // V.G.WZR is another name of V.G.WZ_AKT.R (docs/nc.md).
            "WZ_AKT.R" | "WZR" => (objects::RADIUS, F64),
            "WZ_AKT.WEAR_RADIUS" => (objects::WEAR_RADIUS, F64),
            "WZ_AKT.WEAR_RADIUS_CONT" => (objects::WEAR_RADIUS_CONT, F64),
            "WZ_AKT.WEAR_CONST" => (objects::OTC_WEAR_CONST, F64),
            "OTC_ACTIVE" => (objects::OTC_ON, I32),
            _ => {
                let axis = key.strip_prefix("WZ_AKT.WEAR[")?.strip_suffix(']')?;
                let axis: u16 = axis.parse().ok().filter(|a| *a < 8)?;
                (objects::wear_axis(axis), F64)
            }
        })
    }

    /// Reads an object as a number.
    pub(super) fn read_object(
        &mut self,
        addr: ObjectAddress,
        ty: ValueType,
    ) -> Result<f64, RunErrorKind> {
        let req = Request::Read(addr, ty);
        match self.request(&req)? {
            Reply::Value(Value::F64(v)) => Ok(v),
            Reply::Value(Value::I32(v)) => Ok(f64::from(v)),
            other => Err(unexpected(req, other)),
        }
    }

    /// Writes an object.
    pub(super) fn write(&mut self, addr: ObjectAddress, value: Value) -> Result<(), RunErrorKind> {
        self.send(&Request::Write(addr, value))
    }

    /// `var = value`.
    pub(super) fn assign(&mut self, var: &Var, value: f64) -> Result<(), RunErrorKind> {
        match var {
            Var::R(n) => {
                self.r.insert(*n, value);
            }
            Var::P(n) => {
                self.p.insert(*n, value);
            }
            Var::V { scope, path } => {
                let key = self.path_key(path)?;
                match scope {
                    'P' | 'L' => {
                        self.v.insert(format!("{scope}.{key}"), value);
                    }
                    'G' if key == "WZ_AKT.R" || key == "WZR" => {
                        self.radius_change()?;
                        self.write(objects::RADIUS, Value::F64(value))?;
                    }
                    _ => {
                        let name = format!("V.{scope}.{key}");
                        return Err(RunErrorKind::NotWritable { name });
                    }
                }
            }
        }
        Ok(())
    }
}

impl Vars for Interpreter<'_> {
    fn read(&mut self, var: &Var) -> Result<f64, RunErrorKind> {
        match var {
            // R parameters start at 0, as on the controller.
            Var::R(n) => Ok(self.r.get(n).copied().unwrap_or(0.0)),
            Var::P(n) => self.p.get(n).copied().ok_or_else(|| RunErrorKind::Unset {
                name: format!("P{n}"),
            }),
            Var::V { scope, path } => {
                let key = self.path_key(path)?;
                match scope {
                    'P' | 'L' => self
                        .v
                        .get(&format!("{scope}.{key}"))
                        .copied()
                        .ok_or_else(|| RunErrorKind::Unset {
                            name: format!("V.{scope}.{key}"),
                        }),
                    'G' => match Self::global_object(&key) {
                        Some((addr, ty)) => self.read_object(addr, ty),
                        None => Err(RunErrorKind::UnknownVariable {
                            name: format!("V.G.{key}"),
                        }),
                    },
                    _ => Err(RunErrorKind::ScopeNotImplemented { scope: *scope }),
                }
            }
        }
    }
}
