// Accuracy and coverage cases that the release build runs and the sanitizer
// builds skip: they check figures, not memory or threads, and under the
// sanitizers they would take most of CI's time (docs/reliability.md, "In CI").
#pragma once

#include <gtest/gtest.h>

#ifdef SARMAP_SANITIZED
#define RELEASE_ONLY() GTEST_SKIP() << "accuracy or coverage case: release build only"
inline constexpr bool kSanitizedBuild = true;
#else
#define RELEASE_ONLY() (void)0
inline constexpr bool kSanitizedBuild = false;
#endif
// Loops that try many cases of one kind (bytes flipped one by one, runs
// killed at random moments) take fewer under the sanitizers, as
// `kSanitizedBuild ? fewer : all`: each case costs ten times as much there,
// and the release build and the fuzz job still take them all.

// Cases that only parse saved bytes on one thread (every cut or flipped byte
// of a state) give ThreadSanitizer nothing to check and are its slowest
// cases; the release and ASan builds still run them, and the fuzz job
// covers the parsers.
#ifdef SARMAP_THREAD_SANITIZED
#define NOT_UNDER_TSAN() GTEST_SKIP() << "single-threaded parsing case: the release and ASan builds run it"
#else
#define NOT_UNDER_TSAN() (void)0
#endif
