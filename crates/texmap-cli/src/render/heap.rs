//! Handing the allocator's free memory back to the system once a scene is loaded, keeping
//! the largest blocks out of its arenas from the start, and keeping what a turntable's
//! frames free for the next frame ([`frames_keep_freed_memory`]).
//!
//! Loading decodes each image and builds its mip chain through buffers as large as the
//! image, freed as soon as each texture is made. glibc's allocator keeps such freed blocks
//! for reuse (its mmap threshold rises to 32 MiB after the first large free), so they stay
//! resident while the frames allocate their own buffers beside them: on DamagedHelmet
//! about 60 MB of the peak. `malloc_trim(0)` returns every arena's free pages; a fixed
//! mmap threshold (`keep_large_blocks_unmapped`) keeps the rise from happening. Elsewhere
//! (other allocators, other systems) both do nothing.

/// Blocks of at least this many bytes get their own mapping, unmapped when freed
/// ([`keep_large_blocks_unmapped`]).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD: libc::c_int = 16 << 20;

/// Fixes glibc's mmap threshold at 16 MiB for the whole run (a 1080p frame, a 2048² level
/// in 16 bits or in floats get their own mapping, unmapped when freed) and with it its trim
/// threshold at 128 KiB. Left dynamic, both rise as the load frees its large blocks (the
/// trim threshold to twice the mmap threshold, up to 64 MiB), so the next large buffers
/// come from the arenas and the heap's freed top stays resident: on DamagedHelmet 4 MB of
/// the peak while the frame is drawn and written (206.4 against 202.3 MB). Blocks under
/// 16 MiB (a decoded 2048² RGB image is 12 MiB) stay in the arenas and are reused without
/// new page faults: a 1 MiB threshold also cut the peak, but took 5% more CPU to load.
pub(crate) fn keep_large_blocks_unmapped() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets an allocator parameter; it takes no pointer, and runs
    // before any thread of ours is started.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
    }
}

/// The trim threshold while frames are drawn ([`frames_keep_freed_memory`]), and while a
/// scene loads (glibc's default, what the fixed mmap threshold left).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const FRAMES_TRIM_THRESHOLD: libc::c_int = 256 << 20;
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const LOAD_TRIM_THRESHOLD: libc::c_int = 128 << 10;

/// With `true` (a scene is set up, its frames follow), the memory a frame frees stays with
/// the allocator for the next frame; with `false` (a scene is about to load), the heap's
/// freed top goes back to the system past 128 KiB again. A frame of a large mesh allocates
/// and frees tens of megabytes (transformed vertices, assembled triangles, their bins): at
/// 128 KiB the freed tops went back to the system and every frame faulted them in again
/// (2,200 page faults a frame on the 199,200-triangle sphere at 1080p). The load's peak is
/// untouched (its buffers are freed and returned by [`release_free_memory`] before), and so
/// was DamagedHelmet's one-frame peak (five alternated runs each: 189–194 MB either way).
pub(crate) fn frames_keep_freed_memory(keep: bool) {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets an allocator parameter under the allocator's lock; it takes
    // no pointer, and the allocator is initialized (the process has allocated).
    unsafe {
        let threshold = if keep {
            FRAMES_TRIM_THRESHOLD
        } else {
            LOAD_TRIM_THRESHOLD
        };
        libc::mallopt(libc::M_TRIM_THRESHOLD, threshold);
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    let _ = keep;
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
