//! A physics step that cannot take the run down. rapier asserts on some solver states that are
//! no longer finite (a motor's velocity clamp whose bounds turned NaN when a multibody's
//! augmented mass matrix is too ill-conditioned for `f32`: gram-weight fragments of a decomposed
//! mesh on a body of several kilograms), and an assert panics. A step that panics is a
//! simulation that produced non-finite states, which the checks already fail; its message is
//! kept off stderr, since the failure is reported where it belongs.

use std::cell::Cell;
use std::panic::AssertUnwindSafe;
use std::sync::Once;

thread_local! {
    /// Whether this thread is inside [`guarded`] (its panics are expected and not printed).
    static GUARDED: Cell<bool> = const { Cell::new(false) };
}

/// The panic hook that stays quiet inside [`guarded`], installed once per process.
static QUIET_HOOK: Once = Once::new();

/// Runs `f`; `None` if it panicked.
pub(crate) fn guarded<T>(f: impl FnOnce() -> T) -> Option<T> {
    QUIET_HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !GUARDED.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let was = GUARDED.with(|g| g.replace(true));
    let result = std::panic::catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(was));
    result.ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_inside_is_a_none_and_a_value_comes_through() {
        assert_eq!(guarded(|| 7), Some(7));
        let nan = f32::NAN;
        assert_eq!(guarded(|| 1.0f32.clamp(nan, nan)), None);
        // Still usable afterwards, and nested guards restore the outer state.
        assert_eq!(guarded(|| guarded(|| 3).map(|x| x + 1)), Some(Some(4)));
        assert!(!GUARDED.with(Cell::get));
    }
}
