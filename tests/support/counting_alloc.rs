//! Heap allocations counted on the calling thread, for the no-allocation tests (tests/no_alloc.rs,
//! tests/triggers_no_alloc.rs): the binary's global allocator is this one.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct CountingAllocator;

thread_local! {
    // Counted per thread: the test harness allocates on its own threads at any time.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count_one() {
    let _ = ALLOCATIONS.try_with(|count| count.set(count.get() + 1));
}

pub fn allocations_so_far() -> usize {
    ALLOCATIONS.with(Cell::get)
}

// SAFETY: every call goes to the system allocator with the caller's arguments, under the same contract.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        // SAFETY: the caller's arguments, under GlobalAlloc's contract.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's arguments, under GlobalAlloc's contract.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        // SAFETY: the caller's arguments, under GlobalAlloc's contract.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// The counter itself: a test that counted nothing would pass for any code.
#[test]
fn an_allocation_on_this_thread_is_counted() {
    let before = allocations_so_far();
    let boxed = std::hint::black_box(Box::new(7u64));
    assert_eq!(allocations_so_far(), before + 1);
    drop(boxed);
}
