#pragma once
/// @file atomic_file.h
/// Writing outputs whole or not at all: write to a temporary file beside the target, then rename.
#include <functional>
#include <string>

namespace fs {

/// Calls @p write with a temporary path in the target's folder, then renames it onto @p path.
/// If @p write throws, the temporary file is removed and the target is left untouched.
/// @throws std::runtime_error naming @p path when the rename fails.
void writeAtomically(const std::string& path, const std::function<void(const std::string& tmpPath)>& write);

}  // namespace fs
