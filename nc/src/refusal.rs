//! A parse failure with one message of its own: a leaf every part of the
//! parser may use.

use winnow::error::{ContextError, ErrMode, StrContext};
use winnow::ModalResult;

/// A failure with one message, cut so no alternative hides it.
pub fn refuse<T>(message: &'static str) -> ModalResult<T> {
    let mut e = ContextError::new();
    e.push(StrContext::Label(message));
    Err(ErrMode::Cut(e))
}
