// Forward-pass workspaces shared by the blocks a classifier runs in
// parallel, kept between calls so that a scan's blocks allocate nothing
// after the first. A block borrows one for its forward pass and gives it
// back. Not thread-local storage: a thread waiting inside one block's nested
// kernel loops may run another block meanwhile, and the two must not share
// a workspace. As many exist as blocks ever ran at once.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "engine/semantic/dgcnn/dgcnn_workspace.hpp"

namespace sarmap {

class DgcnnWorkspacePool {
 public:
  // A workspace on loan; returned to the pool when the loan ends.
  class Loan {
   public:
    Loan(DgcnnWorkspacePool& pool, std::unique_ptr<DgcnnWorkspace> workspace)
        : pool_(pool), workspace_(std::move(workspace)) {}
    Loan(const Loan&) = delete;
    Loan& operator=(const Loan&) = delete;
    ~Loan() { pool_.give_back(std::move(workspace_)); }
    DgcnnWorkspace& get() { return *workspace_; }

   private:
    DgcnnWorkspacePool& pool_;
    std::unique_ptr<DgcnnWorkspace> workspace_;
  };

  DgcnnWorkspacePool() = default;
  // A copy starts empty: workspaces are scratch, not state.
  DgcnnWorkspacePool(const DgcnnWorkspacePool&) {}
  DgcnnWorkspacePool& operator=(const DgcnnWorkspacePool&) { return *this; }

  Loan borrow() {
    std::unique_ptr<DgcnnWorkspace> workspace;
    {
      const std::lock_guard lock(mutex_);
      if (!free_.empty()) {
        workspace = std::move(free_.back());
        free_.pop_back();
      }
    }
    if (!workspace) workspace = std::make_unique<DgcnnWorkspace>();
    return Loan(*this, std::move(workspace));
  }

 private:
  void give_back(std::unique_ptr<DgcnnWorkspace> workspace) {
    const std::lock_guard lock(mutex_);
    free_.push_back(std::move(workspace));
  }

  std::mutex mutex_;
  std::vector<std::unique_ptr<DgcnnWorkspace>> free_;
};

}  // namespace sarmap
