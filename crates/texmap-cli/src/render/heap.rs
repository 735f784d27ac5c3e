//! Handing the allocator's free memory back to the system once a scene is loaded.
//!
//! Loading decodes each image and builds its mip chain through buffers as large as the
//! image, freed as soon as each texture is made. glibc's allocator keeps such freed blocks
//! for reuse (its mmap threshold rises to 32 MiB after the first large free), so they stay
//! resident while the frames allocate their own buffers beside them: on DamagedHelmet
//! about 60 MB of the peak. `malloc_trim(0)` returns every arena's free pages. Elsewhere
//! (other allocators, other systems) this does nothing.

/// Returns the allocator's free pages to the system (glibc on Linux; a no-op elsewhere).
pub(crate) fn release_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `malloc_trim` only releases memory the allocator holds free; it takes no
    // pointer and may be called at any time from any thread.
    unsafe {
        libc::malloc_trim(0);
    }
}
