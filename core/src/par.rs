//! Independent work split over threads, merged in a fixed order: the one
//! place of core that may start a thread.
//!
//! [`map`] applies a pure function to every item of a slice and returns
//! the results in the items' order. With the `threads` feature on a
//! native target and more than one thread asked for, the items are dealt
//! round-robin to scoped threads (`std::thread::scope`: no pool, no global
//! state, every thread joined before `map` returns); otherwise it is a
//! plain loop. Either way result i is `f(&items[i])`, computed from the
//! same inputs by the same code, so a solve gives the same bits with 1, 2
//! or 16 threads: the thread count decides only which core computes what,
//! never what is computed nor the order in which the results are read.
//! The browser's build (wasm32) never compiles a thread.
//!
//! The thread count comes in through [`crate::slam::types::SolveOptions::threads`]
//! (1 by default: core reads nothing of the machine; the CLI, the service
//! and Python pass the machine's available parallelism).

/// Results of `f` over `items`, in the items' order, computed on up to
/// `threads` threads (module doc). A panic in `f` is raised again here.
pub fn map<T, R, F>(threads: usize, items: &[T], f: F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync,
{
    #[cfg(all(feature = "threads", not(target_arch = "wasm32")))]
    if threads > 1 && items.len() > 1 {
        return split(threads.min(items.len()), items, &f);
    }
    let _ = threads;
    items.iter().map(f).collect()
}

/// [`map`] over `t >= 2` threads: thread w computes the items w, w + t,
/// w + 2t, ...; the results are then read back in the items' order.
#[cfg(all(feature = "threads", not(target_arch = "wasm32")))]
#[allow(clippy::disallowed_methods)]
fn split<T, R, F>(t: usize, items: &[T], f: &F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync,
{
    let stride = |w: usize| -> Vec<R> { items.iter().skip(w).step_by(t).map(f).collect() };
    let mut parts: Vec<std::vec::IntoIter<R>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (1..t).map(|w| scope.spawn(move || stride(w))).collect();
        let mut parts = vec![stride(0).into_iter()];
        for h in handles {
            match h.join() {
                Ok(p) => parts.push(p.into_iter()),
                Err(e) => std::panic::resume_unwind(e),
            }
        }
        parts
    });
    (0..items.len())
        .map(|i| parts[i % t].next().expect("one result per item"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::map;

    /// The results come back in the items' order whatever the thread
    /// count, also with more threads than items and with no items.
    #[test]
    fn results_in_item_order_for_any_thread_count() {
        let items: Vec<u64> = (0..1000).collect();
        let want: Vec<u64> = items.iter().map(|x| x * x + 7).collect();
        for t in [0, 1, 2, 3, 16, 5000] {
            assert_eq!(map(t, &items, |x| x * x + 7), want, "{t} threads");
        }
        assert!(map(4, &[] as &[u64], |x| *x).is_empty());
        assert_eq!(map(4, &[9u64], |x| *x), [9]);
    }

    /// A panic in the function reaches the caller (not swallowed by a
    /// thread).
    #[test]
    #[should_panic(expected = "item 777")]
    fn a_panic_reaches_the_caller() {
        let items: Vec<u64> = (0..1000).collect();
        map(4, &items, |&x| {
            assert!(x != 777, "item {x}");
            x
        });
    }
}
