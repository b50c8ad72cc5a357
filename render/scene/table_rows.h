#pragma once
/// @file table_rows.h
/// A first-shot table's factors by patch: the one place in render/ that reads the table's CSR
/// arrays (FirstShotTable::rowStart, sampleIndex, factor and visible; common/table/firstshot.h).
///
/// Row j holds the factors of patch j in the table's order; each factor comes as its position k in
/// that order (the index of the per-factor arrays the renderer keeps beside the table, such as
/// FirstShotLighting's visible fractions), its light sample i and r_ij:
///
///   const TableRows rows(table);
///   for (const TableFactor f : rows[j]) sum += table.samples[f.sample].emission * f.r;
#include <cstddef>
#include <cstdint>
#include <iterator>

#include "common/table/firstshot.h"
#include "common/util/hash.h"

namespace firstshot {

/// One factor r_ij of a table.
struct TableFactor {
  uint64_t index = 0;   ///< k: its position in the table's factor order
  uint32_t sample = 0;  ///< i: index into FirstShotTable::samples
  float r = 0.0f;       ///< r_ij (units by the sample's kind, common/table/firstshot.h)
};

/// The factors of one patch (or of the whole table), positions [first(), end()) of the table's order.
class TableRow {
 public:
  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = TableFactor;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = TableFactor;

    Iterator() = default;
    TableFactor operator*() const { return TableFactor{k_, sample_[k_], factor_[k_]}; }
    Iterator& operator++() {
      ++k_;
      return *this;
    }
    Iterator operator++(int) {
      Iterator old = *this;
      ++k_;
      return old;
    }
    bool operator==(const Iterator& o) const { return k_ == o.k_; }
    bool operator!=(const Iterator& o) const { return k_ != o.k_; }

   private:
    friend class TableRow;
    Iterator(const uint32_t* sample, const float* factor, uint64_t k) : sample_(sample), factor_(factor), k_(k) {}
    const uint32_t* sample_ = nullptr;
    const float* factor_ = nullptr;
    uint64_t k_ = 0;
  };

  TableRow() = default;
  TableRow(const uint32_t* sample, const float* factor, uint64_t first, uint64_t end)
      : sample_(sample), factor_(factor), first_(first), end_(end) {}

  Iterator begin() const { return Iterator(sample_, factor_, first_); }
  Iterator end() const { return Iterator(sample_, factor_, end_); }
  uint64_t first() const { return first_; }  ///< position of the row's first factor
  uint64_t size() const { return end_ - first_; }
  bool empty() const { return first_ == end_; }

 private:
  const uint32_t* sample_ = nullptr;
  const float* factor_ = nullptr;
  uint64_t first_ = 0, end_ = 0;
};

/// The rows of a table, which must outlive this and have passed check() (RenderScene does that).
class TableRows {
 public:
  TableRows() = default;  ///< no table: no rows
  explicit TableRows(const FirstShotTable& table) : table_(&table) {}

  uint32_t patches() const { return table_ ? static_cast<uint32_t>(table_->rowStart.size()) - 1 : 0; }
  /// Number of factors, the size of a per-factor array.
  uint64_t factors() const { return table_ ? table_->factor.size() : 0; }
  /// The factors of patch @p j.
  TableRow operator[](uint32_t j) const {
    return TableRow(table_->sampleIndex.data(), table_->factor.data(), table_->rowStart[j], table_->rowStart[j + 1]);
  }
  /// Every factor, in the table's order.
  TableRow all() const { return TableRow(table_->sampleIndex.data(), table_->factor.data(), 0, factors()); }
  /// The factor at position @p k (kept from a row).
  TableFactor at(uint64_t k) const { return TableFactor{k, table_->sampleIndex[k], table_->factor[k]}; }
  /// Whether the table came with its visible fractions V_ij (FirstShotTable::visible, readFirstShot).
  bool hasStoredVisible() const { return table_ && table_->visible.size() == table_->factor.size(); }
  /// V_ij as stored for the factor at position @p k (needs hasStoredVisible(); −1 for other kinds than
  /// point lights and area vertices).
  float storedVisible(uint64_t k) const { return table_->visible[k]; }

  /// Why @p table's rows are not well formed (sizes against its patches, row starts, sample
  /// indices against its samples), or nullptr if they are.
  static const char* check(const FirstShotTable& table);
  /// Adds the rows (row starts, sample indices, factors, as bytes) to @p h.
  static void hash(const FirstShotTable& table, Hasher& h) {
    h.bytes(table.rowStart.data(), table.rowStart.size() * sizeof(uint64_t));
    h.bytes(table.sampleIndex.data(), table.sampleIndex.size() * sizeof(uint32_t));
    h.bytes(table.factor.data(), table.factor.size() * sizeof(float));
  }

 private:
  const FirstShotTable* table_ = nullptr;
};

}  // namespace firstshot
