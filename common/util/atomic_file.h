#pragma once
/// @file atomic_file.h
/// Writing outputs whole or not at all: write to a temporary file beside the target, then rename.
#include <functional>
#include <string>

namespace firstshot {

/// What writeAtomically does when SIGINT/SIGTERM has arrived (common/util/interrupt.h).
enum class OnInterrupt {
  Discard,  ///< remove the temporary file, leave the target untouched, throw Interrupted (outputs)
  Keep,     ///< finish the write and rename as usual (a checkpoint saved because of the signal)
};

/// Calls @p write with a temporary path in the target's folder, then renames it onto @p path.
/// If @p write throws, the temporary file is removed and the target is left untouched. If an
/// interrupting signal arrived before the rename and @p onInterrupt is Discard, the same happens
/// and Interrupted is thrown ("PATH was not written").
/// @throws std::runtime_error naming @p path when the rename fails.
void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write,
                     OnInterrupt onInterrupt = OnInterrupt::Discard);

}  // namespace firstshot
