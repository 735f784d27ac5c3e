//! Handing the allocator's free memory back to the system once a scene is loaded, keeping
//! the largest blocks out of its arenas from the start, and keeping what is freed between
//! two trims for the next buffers ([`set_up_allocator`]).
//!
//! Loading decodes each image and builds its mip chain through buffers as large as the
//! image, freed as soon as each texture is made. glibc's allocator keeps such freed blocks
//! for reuse (its mmap threshold rises to 32 MiB after the first large free), so they stay
//! resident while the frames allocate their own buffers beside them: on DamagedHelmet
//! about 60 MB of the peak. `malloc_trim(0)` returns every arena's free pages once the
//! scene is set up (and before a batch's next scene loads); a fixed mmap threshold keeps the
//! rise from happening. Elsewhere (other allocators, other systems) both do nothing.

/// Blocks of at least this many bytes get their own mapping, unmapped when freed
/// ([`set_up_allocator`]).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD: libc::c_int = 16 << 20;

/// Freed memory at the top of a heap past this stays with the allocator until
/// [`release_free_memory`].
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const TRIM_THRESHOLD: libc::c_int = 256 << 20;

/// Fixes glibc's mmap threshold at 16 MiB and its trim threshold at 256 MiB for the whole
/// run.
///
/// The mmap threshold: a 1080p frame and a 2048² level in 16 bits get their own mapping,
/// unmapped when freed. Left dynamic, it rises as the load frees its large blocks (and the
/// trim threshold with it, to twice the mmap threshold), so the next large buffers come from
/// the arenas and stay resident: on DamagedHelmet 4 MB of the peak while the frame is drawn
/// and written (206.4 against 202.3 MB). Blocks under 16 MiB (a decoded 2048² RGB image is
/// 12 MiB) stay in the arenas; a 1 MiB threshold also cut the peak, but took 5% more CPU to
/// load.
///
/// The trim threshold: what a load or a frame frees stays for the next buffers instead of
/// being faulted in again (a page fault costs about 1.4 µs on the 2-core VM). A frame of a
/// large mesh allocates and frees tens of megabytes (transformed vertices, assembled
/// triangles, their bins): at glibc's 128 KiB every frame faulted them in again (2,200 page
/// faults a frame on the 199,200-triangle sphere at 1080p). Loading DamagedHelmet with
/// the load's tops handed back as at 128 KiB: 63,800 page faults against 54,700 (one
/// thread), its load + setup 0.931× (ten alternated rounds), its peak RSS 175.2 → 178.9 MB.
/// What a load frees goes back by [`release_free_memory`] before the frames, and what a
/// batch's scene freed before the next scene loads.
pub(crate) fn set_up_allocator() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets an allocator parameter; it takes no pointer, and runs
    // before any thread of ours is started.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
        libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD);
    }
}

/// Returns the allocator's free pages to the system (glibc on Linux; a no-op elsewhere).
pub(crate) fn release_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `malloc_trim` only releases memory the allocator holds free; it takes no
    // pointer and may be called at any time from any thread.
    unsafe {
        libc::malloc_trim(0);
    }
}
