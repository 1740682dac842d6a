//! The typed block model: what one line of an NC program says.

use crate::expr::{Expr, Var};

/// One block (one line) of an NC program.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Block {
    /// Line of the program, from 1.
    pub line: usize,
    /// The block number of the `N` word, if any.
    pub number: Option<u32>,
    /// The block's words and commands, in the order written.
    pub items: Vec<Item>,
    /// The column (from 1, in characters) where each item starts: the
    /// position a run-time error of that item names.
    pub columns: Vec<usize>,
}

impl Block {
    /// The column of item `k`, 1 when it is not known.
    pub fn column(&self, k: usize) -> usize {
        self.columns.get(k).copied().unwrap_or(1)
    }
}

/// One word or command of a block.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// `%name`: the program header.
    ProgramName(String),
    /// A G function.
    G(GCode),
    /// An axis word: `X10`, `B45`, `Y[R1*2]`.
    Axis(Axis, Expr),
    /// A circle centre word (`I`, `J`, `K`), relative to the start point.
    Centre(CentreAxis, Expr),
    /// `F`: path feed.
    Feed(Expr),
    /// `D`: tool data set (`D0` = none).
    ToolData(Expr),
    /// `T`: tool number.
    Tool(Expr),
    /// `M`: machine function (`M30` ends the program).
    M(u32),
    /// `R`: the radius of an arc given by its end point (`G2 X10 R5`);
    /// negative for an arc of more than 180°.
    ArcRadius(Expr),
    /// `#TRC [OPTION ..]`: its first option's name (options of the radius
    /// correction are not in this emulator: an error at run time).
    TrcOption(String),
    /// `#TANGFEED [RMIN=..]` (or `#SET TANGFEED RMIN [..]`): the smallest
    /// programmed arc radius whose feed G11 adapts; `None` for 0.
    TangFeed(Option<Expr>),
    /// `R1 = expr`, `V.P.NAME = expr`, `V.G.WZ_AKT.R = expr`.
    Assign(Var, Expr),
    /// `$FOR var = start, end, step`.
    For {
        /// The counter.
        var: Var,
        /// First value.
        start: Box<Expr>,
        /// Last value (inclusive).
        end: Box<Expr>,
        /// Increment per pass.
        step: Box<Expr>,
    },
    /// `$ENDFOR`.
    EndFor,
    /// `$IF condition`.
    If(Expr),
    /// `$ELSE`.
    Else,
    /// `$ENDIF`.
    EndIf,
    /// `$WHILE condition`.
    While(Expr),
    /// `$ENDWHILE`.
    EndWhile,
    /// `#OTC ON|OFF [...]` or `#OTC [...]`.
    Otc(OtcCommand),
    /// `#set ToolParam(line; column; value)#`.
    SetToolParam {
        /// Data set (D number), 1..255.
        line: Box<Expr>,
        /// Column, 0..15.
        column: Box<Expr>,
        /// The value written.
        value: Box<Expr>,
    },
    /// `#get ToolParam(line; column; R-parameter)#`.
    GetToolParam {
        /// Data set (D number), 1..255.
        line: Box<Expr>,
        /// Column, 0..15.
        column: Box<Expr>,
        /// The parameter that receives the value.
        target: Var,
    },
    /// `#KIN ID[n]`: kinematic type.
    Kinematic(u32),
    /// `#TRAFO ON` (true) / `#TRAFO OFF` (false).
    Trafo(bool),
    /// `#HSC ON[...]` / `#HSC OFF`: accepted, options kept as written.
    Hsc {
        /// ON (true) or OFF (false).
        on: bool,
        /// The text between the brackets, not interpreted.
        options: String,
    },
}

impl Item {
    /// Whether it is a `$` control statement (`$FOR`, `$ENDFOR`, `$IF`,
    /// `$ELSE`, `$ENDIF`, `$WHILE`, `$ENDWHILE`).
    pub fn is_control(&self) -> bool {
        matches!(
            self,
            Item::For { .. }
                | Item::EndFor
                | Item::If(_)
                | Item::Else
                | Item::EndIf
                | Item::While(_)
                | Item::EndWhile
        )
    }
}

/// The G functions this parser knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GCode {
    /// G0: rapid traverse.
    Rapid,
    /// G1: straight line at feed.
    Linear,
    /// G2: circle clockwise.
    ArcCw,
    /// G3: circle counter-clockwise.
    ArcCcw,
    /// G05: tangential TRC selection/deselection (non-modal).
    TrcTangential,
    /// G10: constant feed (feed adaption off).
    FeedConstant,
    /// G11: adapted feed.
    FeedAdapted,
    /// G17: X-Y plane.
    PlaneXy,
    /// G18: Z-X plane.
    PlaneZx,
    /// G19: Y-Z plane.
    PlaneYz,
    /// G25: linear transition blocks.
    TransitionLinear,
    /// G26: circular transition blocks.
    TransitionCircular,
    /// G40: TRC off.
    TrcOff,
    /// G41: TRC left of the contour.
    TrcLeft,
    /// G42: TRC right of the contour.
    TrcRight,
    /// G90: absolute dimensions.
    Absolute,
    /// G91: incremental dimensions.
    Incremental,
    /// G138: direct TRC selection/deselection.
    TrcDirect,
    /// G139: indirect TRC selection/deselection.
    TrcIndirect,
    /// G140: contour masking off.
    MaskingOff,
    /// G141: contour masking on.
    MaskingOn,
    /// G236: direct TRC selection/deselection on the path (runs as G138).
    TrcOnPath,
    /// G237: perpendicular TRC selection/deselection.
    TrcPerpendicular,
    /// G238: TRC selection at an inside corner of a closed contour.
    TrcInsideCorner,
    /// G239: direct TRC selection, deselection without a block.
    TrcWithoutBlock,
}

impl GCode {
    /// The G function of a number, `None` for one this parser does not know.
    pub fn from_number(n: u32) -> Option<GCode> {
        use GCode::*;
        Some(match n {
            0 => Rapid,
            1 => Linear,
            2 => ArcCw,
            3 => ArcCcw,
            5 => TrcTangential,
            10 => FeedConstant,
            11 => FeedAdapted,
            17 => PlaneXy,
            18 => PlaneZx,
            19 => PlaneYz,
            25 => TransitionLinear,
            26 => TransitionCircular,
            40 => TrcOff,
            41 => TrcLeft,
            42 => TrcRight,
            90 => Absolute,
            91 => Incremental,
            138 => TrcDirect,
            139 => TrcIndirect,
            140 => MaskingOff,
            141 => MaskingOn,
            236 => TrcOnPath,
            237 => TrcPerpendicular,
            238 => TrcInsideCorner,
            239 => TrcWithoutBlock,
            _ => return None,
        })
    }
}

/// An axis address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    /// X.
    X,
    /// Y.
    Y,
    /// Z.
    Z,
    /// A (rotary about X).
    A,
    /// B (rotary about Y; the tool orientation of TOOL_DIR).
    B,
    /// C (rotary about Z).
    C,
    /// U.
    U,
    /// V.
    V,
}

impl Axis {
    /// The axis of an address letter (upper case).
    pub fn from_letter(c: char) -> Option<Axis> {
        Some(match c {
            'X' => Axis::X,
            'Y' => Axis::Y,
            'Z' => Axis::Z,
            'A' => Axis::A,
            'B' => Axis::B,
            'C' => Axis::C,
            'U' => Axis::U,
            'V' => Axis::V,
            _ => return None,
        })
    }
}

/// A circle centre address: I (X), J (Y), K (Z).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CentreAxis {
    /// I: centre offset in X.
    I,
    /// J: centre offset in Y.
    J,
    /// K: centre offset in Z.
    K,
}

/// `#OTC`: switching and options of online tool compensation.
#[derive(Debug, Clone, PartialEq)]
pub struct OtcCommand {
    /// `Some(true)` for ON, `Some(false)` for OFF, `None` for `#OTC[...]`.
    pub switch: Option<bool>,
    /// The options in the brackets, in the order written.
    pub options: Vec<OtcOption>,
}

/// One option of `#OTC [...]`.
#[derive(Debug, Clone, PartialEq)]
pub enum OtcOption {
    /// Processing type.
    Kind(OtcKind),
    /// Mode.
    Mode(OtcMode),
    /// `WEAR_CONST=..`: the programmed wear constant, 0.1 µm/m.
    WearConst(Expr),
    /// `WEAR_CONST_TOOL`: back to the tool data's wear constant.
    WearConstTool,
    /// `ACC_WEIGHT=..`: acceleration weighting in percent.
    AccWeight(Expr),
}

/// OTC processing type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OtcKind {
    /// RADIUS.
    Radius,
    /// LENGTH.
    Length,
    /// TOOL_DIR.
    ToolDir,
    /// SURF_NORM_DIR.
    SurfNormDir,
}

/// OTC mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OtcMode {
    /// DISC: discrete, PLC input only.
    Disc,
    /// CONT: continuous, computed from the path.
    Cont,
    /// AUTO: both.
    Auto,
}
