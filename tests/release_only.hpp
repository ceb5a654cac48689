// Accuracy and coverage cases that the release build runs and the sanitizer
// builds skip: they check figures, not memory or threads, and under the
// sanitizers they would take most of CI's time (docs/reliability.md, "In CI").
#pragma once

#include <gtest/gtest.h>

#ifdef SARMAP_SANITIZED
#define RELEASE_ONLY() GTEST_SKIP() << "accuracy or coverage case: release build only"
#else
#define RELEASE_ONLY() (void)0
#endif
