//! Evaluation of expressions: numbers, parameters, variables, operators
//! and functions (angles in degrees).

use crate::expr::{BinOp, Expr, Func};
use crate::Var;

/// Where expression values come from: parameters and variables.
pub trait Vars {
    /// The value of `var`, or why it has none.
    fn read(&mut self, var: &Var) -> Result<f64, String>;
}

/// The value of `expr`; errors: an unset variable, a division by zero, a
/// result that is not a finite number.
pub fn eval(expr: &Expr, vars: &mut dyn Vars) -> Result<f64, String> {
    let v = match expr {
        Expr::Number(n) => *n,
        Expr::Var(var) => vars.read(var)?,
        Expr::Neg(e) => -eval(e, vars)?,
        Expr::Binary(op, a, b) => binary(*op, eval(a, vars)?, eval(b, vars)?)?,
        Expr::Call(f, e) => call(*f, eval(e, vars)?),
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err("the expression has no finite value".into())
    }
}

fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

fn binary(op: BinOp, a: f64, b: f64) -> Result<f64, String> {
    Ok(match op {
        BinOp::Or => truth(a != 0.0 || b != 0.0),
        BinOp::And => truth(a != 0.0 && b != 0.0),
        BinOp::Eq => truth(a == b),
        BinOp::Ne => truth(a != b),
        BinOp::Lt => truth(a < b),
        BinOp::Le => truth(a <= b),
        BinOp::Gt => truth(a > b),
        BinOp::Ge => truth(a >= b),
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div if b == 0.0 => return Err("division by zero".into()),
        BinOp::Div => a / b,
    })
}

fn call(f: Func, x: f64) -> f64 {
    match f {
        Func::Sin => x.to_radians().sin(),
        Func::Cos => x.to_radians().cos(),
        Func::Tan => x.to_radians().tan(),
        Func::Asin => x.asin().to_degrees(),
        Func::Acos => x.acos().to_degrees(),
        Func::Atan => x.atan().to_degrees(),
        Func::Abs => x.abs(),
        Func::Sqrt => x.sqrt(),
        Func::Int => x.trunc(),
        Func::Round => x.round(),
        Func::Exp => x.exp(),
        Func::Ln => x.ln(),
    }
}
