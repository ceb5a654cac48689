// Where the DGCNN fixtures live (the reference blocks, logits and models
// written by tools/python/, under tests/data/dgcnn/).
#pragma once

#include <string>

namespace sarmap::testing {

inline const std::string kDgcnnDataDir = std::string(SARMAP_TEST_DATA_DIR) + "/dgcnn/";

}  // namespace sarmap::testing
