//! Evaluation of expressions: numbers, parameters, variables, operators
//! and functions (angles in degrees).

use super::RunErrorKind;
use crate::expr::{BinOp, Expr, Func};
use crate::Var;

/// Where expression values come from: parameters and variables.
pub trait Vars {
    /// The value of `var`, or why it has none.
    fn read(&mut self, var: &Var) -> Result<f64, RunErrorKind>;
}

/// The value of `expr`; errors: an unset variable, a division by zero, a
/// result (or a step of a chain) that is not a finite number.
///
/// A chain of operators is folded left to right in a loop, so the stack
/// this needs grows with the expression's nesting (bounded by the parser,
/// [`crate::MAX_EXPR_NESTING`]), not with its length.
pub fn eval(expr: &Expr, vars: &mut dyn Vars) -> Result<f64, RunErrorKind> {
    let v = match expr {
        Expr::Number(n) => *n,
        Expr::Var(var) => vars.read(var)?,
        Expr::Neg(e) => -eval(e, vars)?,
        Expr::Chain(first, rest) => {
            let mut acc = eval(first, vars)?;
            for (op, e) in rest.iter() {
                acc = finite(binary(*op, acc, eval(e, vars)?)?)?;
            }
            acc
        }
        Expr::Call(f, e) => call(*f, eval(e, vars)?),
    };
    finite(v)
}

fn finite(v: f64) -> Result<f64, RunErrorKind> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(RunErrorKind::NotFinite)
    }
}

fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

fn binary(op: BinOp, a: f64, b: f64) -> Result<f64, RunErrorKind> {
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
        BinOp::Div if b == 0.0 => return Err(RunErrorKind::DivisionByZero),
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
