//! Cooperative cancellation of one piece of work (a `holoc batch` job past its time limit).
//!
//! A [`Token`] is a flag and the name of the stage the work is in. The work's thread installs
//! it with [`Token::install`]; stages mark where they are with [`stage`] and long loops ask
//! [`requested`] (one thread-local read: nothing changes for work that installed no token, as
//! every command but `holoc batch`). Work that sees the flag stops early; its caller throws its
//! result away, so a cancelled run never produces an output and outputs never depend on time.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// The cancellation flag of one piece of work, shared between it and its watcher.
#[derive(Debug, Default)]
pub struct Token {
    cancelled: AtomicBool,
    stage: Mutex<&'static str>,
}

thread_local! {
    static CURRENT: RefCell<Option<Arc<Token>>> = const { RefCell::new(None) };
}

impl Token {
    /// A token that is not cancelled, in stage `start`.
    pub fn new(start: &'static str) -> Arc<Token> {
        Arc::new(Token { cancelled: AtomicBool::new(false), stage: Mutex::new(start) })
    }

    /// Asks the work to stop.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::SeqCst);
    }

    /// Whether the work was asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// The stage the work said it was in last.
    pub fn stage(&self) -> &'static str {
        *self.stage.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Marks the stage the work is in.
    pub fn set_stage(&self, stage: &'static str) {
        *self.stage.lock().unwrap_or_else(std::sync::PoisonError::into_inner) = stage;
    }

    /// Makes this token the current thread's (until the thread ends or another is installed).
    pub fn install(self: &Arc<Token>) {
        CURRENT.with(|c| *c.borrow_mut() = Some(Arc::clone(self)));
    }
}

/// The current thread's token, to install on the threads its work fans out to.
pub fn current() -> Option<Arc<Token>> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Makes `token` the current thread's until the returned guard is dropped, which puts back the
/// token the thread had (for a piece of work run on a pool thread that others share).
pub fn scoped(token: Option<Arc<Token>>) -> Scope {
    let before = CURRENT.with(|c| std::mem::replace(&mut *c.borrow_mut(), token));
    Scope { before }
}

/// The guard of [`scoped`].
#[must_use = "the token is put back when the guard is dropped"]
pub struct Scope {
    before: Option<Arc<Token>>,
}

impl Drop for Scope {
    fn drop(&mut self) {
        let before = self.before.take();
        CURRENT.with(|c| *c.borrow_mut() = before);
    }
}

/// Whether the current thread's work was asked to stop (false without a token).
pub fn requested() -> bool {
    CURRENT.with(|c| c.borrow().as_ref().is_some_and(|t| t.is_cancelled()))
}

/// Marks the stage the current thread's work is in (nothing without a token).
pub fn stage(name: &'static str) {
    CURRENT.with(|c| {
        if let Some(t) = c.borrow().as_ref() {
            t.set_stage(name);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_token_is_seen_only_on_its_thread() {
        assert!(!requested());
        let token = Token::new("start");
        token.install();
        stage("solve");
        assert_eq!(token.stage(), "solve");
        assert!(!requested());
        token.cancel();
        assert!(requested());
        std::thread::spawn(|| assert!(!requested())).join().expect("thread");
    }

    #[test]
    fn a_scoped_token_goes_with_the_work_and_is_put_back() {
        let job = Token::new("solve");
        job.cancel();
        let given = Some(Arc::clone(&job));
        std::thread::spawn(move || {
            assert!(!requested());
            {
                let _scope = scoped(given);
                assert!(requested());
            }
            // The pool thread's own (none) is back.
            assert!(!requested());
        })
        .join()
        .expect("thread");
    }
}
