//! Heap bytes of one world's data by part, after 300 steps under random controls: the scratch a
//! batch's threads hold and what each world keeps (`step::data::Kept`).
//! `cargo run --release --example world_memory -- model.xml`
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

/// The system allocator, counting the bytes live.
struct Counting;
static LIVE: AtomicIsize = AtomicIsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        LIVE.fetch_add(l.size() as isize, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size() as isize, Ordering::Relaxed);
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        LIVE.fetch_add(n as isize - l.size() as isize, Ordering::Relaxed);
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

fn kb() -> f64 {
    LIVE.load(Ordering::Relaxed) as f64 / 1024.0
}

/// Drops `part` and prints the bytes that freed.
fn free<T>(name: &str, part: T) {
    let before = kb();
    drop(part);
    println!("{name:>34} {:6.1} kB", before - kb());
}

fn main() {
    let path = std::env::args().nth(1).expect("usage: world_memory MODEL.xml");
    let m = sinew::Model::from_mjcf_file(std::path::Path::new(&path)).unwrap();
    let mut s = sinew::State::new(&m);
    let mut x: u64 = 1;
    for k in 0..300 {
        if k % 10 == 0 {
            for c in s.ctrl.iter_mut() {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
                *c = ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0;
            }
        }
        s.step(&m);
    }
    let d = &mut s.data;
    let mut kept = sinew::step::data::Kept::default();
    d.swap_kept(&mut kept);
    free("scratch held by the batch's threads", std::mem::take(d));
    println!("{:>34} {:6.1} kB", "a world's keeping itself", std::mem::size_of::<sinew::step::data::Kept>() as f64 / 1024.0);
    d.swap_kept(&mut kept);
    free("kinematics computed ahead", std::mem::take(&mut d.dynamics.ahead));
    free("contacts", std::mem::take(&mut d.coll.contacts));
    free("collision poses and caches", std::mem::take(&mut d.coll));
    free("forces the rows applied", std::mem::take(&mut d.constraints.applied));
    free("history", std::mem::take(&mut d.constraints.history));
    free("feed-forward, counters", std::mem::take(&mut d.constraints));
    free("energy bound", std::mem::take(&mut d.energy));
}
