#pragma once
/// @file memory_limit.h
/// A clear error instead of std::bad_alloc or the out-of-memory killer: before allocating a buffer
/// whose size follows from the input (patches, item buffers, images), the tools compare its size
/// with the machine's physical memory and reject the input that cannot fit.
#include <cstdint>
#include <string>

namespace firstshot {

/// Physical memory of this machine, bytes (sysconf); 0 if it cannot be told.
uint64_t physicalMemoryBytes();

/// Throws InputError(@p file, @p element, "… needs N GB for @p what, more than this machine's M GB of
/// memory; @p hint") when @p bytes exceeds the physical memory (unknown memory: no limit). @p bytes is a
/// double so that a product of input values cannot overflow before it is checked.
void requireMemory(double bytes, const std::string& file, const std::string& element, const std::string& what,
                   const std::string& hint);

}  // namespace firstshot
