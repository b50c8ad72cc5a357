#pragma once
/// @file checkpoint.h
/// Render checkpoints (firstshot-render --checkpoint / --resume; docs/robustness.md): the film's
/// raw sums saved so that a later run continues the render and ends with the same image, bit for
/// bit, as an uninterrupted one. Little-endian binary:
///   "FSRESUME", u32 version (1), u32 width, u32 height, u32 length + key text (one "name=value"
///   line per entry of the CheckpointKey), u32 passes (the sample indices every pixel holds),
///   per pixel (row-major) f64 Σ L[3], then Σ L²[3], Σ albedo[3], Σ normal[3] (four arrays),
///   u32 samples per pixel, u64 checksum (common/util/hash.h Hasher over every byte before it), "FSCKEND\0"
///   (the frame of common/util/binary_file.h: header, checksum trailer, atomic write, checked reads).
/// A pixel may hold more samples than `passes` (a render interrupted in the middle of a pass);
/// resuming with RenderOptions::skipTaken takes exactly the samples each pixel lacks.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "render/output/film.h"

namespace firstshot {

/// Everything that decides a render's image, as (name, value) pairs, e.g. ("integrator", "path"),
/// ("seed", "1"), ("scene-file", content hash). A checkpoint is used only with an equal key.
using CheckpointKey = std::vector<std::pair<std::string, std::string>>;

/// Writes @p film's sums with @p key to @p path atomically (temporary file, then rename), also
/// after SIGINT/SIGTERM (OnInterrupt::Keep). @throws std::runtime_error on I/O failure.
void writeCheckpoint(const std::string& path, const CheckpointKey& key, const Film& film);

/// Reads and checks a checkpoint (magic, version, size, checksum, then @p key and the film size)
/// and restores its sums into @p film. @return the passes every pixel holds (the smallest sample
/// count). @throws InputError naming @p path and what is wrong or what does not match (exit code 2).
int readCheckpoint(const std::string& path, const CheckpointKey& key, Film& film);

/// The key of the checkpoint at @p path (checked as readCheckpoint() checks the file up to it), e.g. to learn
/// which integrator --integrator auto chose for the render it holds. @throws InputError as readCheckpoint().
CheckpointKey readCheckpointKey(const std::string& path);

/// A file's content hash as 16 hex digits, for keys; "none" if @p path is empty or does not exist.
std::string fileContentHash(const std::string& path);

}  // namespace firstshot
