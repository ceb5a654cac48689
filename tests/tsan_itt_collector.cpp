// ThreadSanitizer build only (the tsan preset; docs/reliability.md,
// "ThreadSanitizer"). Debian's oneTBB is not built with TSan, so TSan cannot
// see the synchronisation inside libtbb (task hand-off to a worker, the wait
// for a parallel_for's tasks) and would report every parallel loop's inputs
// and outputs as races. oneTBB reports those points itself to Intel's ITT
// tool API (the hooks Intel Inspector uses): from inside libtbb, and from its
// headers when TBB_USE_PROFILING_TOOLS=2 (set by the preset). libtbb loads the
// collector named by INTEL_LIBITTNOTIFY64 (INTEL_ITTNOTIFY_GROUPS=sync asks for
// the sync group); this is that collector, turning each "released" into a TSan
// release and each "acquired" into a TSan acquire on the same address. The
// rest of the ITT API stays unimplemented (libtbb treats it as absent).
extern "C" {
void __tsan_acquire(void* address);
void __tsan_release(void* address);

// Its presence tells ITT's loader this collector takes the current API.
__attribute__((visibility("default"))) const char* __itt_api_version() { return "sarmap-tsan"; }
__attribute__((visibility("default"))) void __itt_sync_acquired(void* address) { __tsan_acquire(address); }
__attribute__((visibility("default"))) void __itt_sync_releasing(void* address) { __tsan_release(address); }
}
