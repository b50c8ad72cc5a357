// TableRows (render/scene/table_rows.h): the rows of a first-shot table's CSR arrays, factor by
// factor, and the check of their shape.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "render/scene/table_rows.h"

using namespace firstshot;

namespace {

/// Three patches: two factors on patch 0, none on patch 1, three on patch 2; two light samples.
FirstShotTable smallTable() {
  FirstShotTable t;
  t.mesh.patches.resize(3);
  t.samples.resize(2);
  t.rowStart = {0, 2, 2, 5};
  t.sampleIndex = {0, 1, 1, 0, 1};
  t.factor = {0.5f, 0.25f, 1.0f, 2.0f, 3.0f};
  return t;
}

}  // namespace

TEST(TableRows, RowsGiveEachFactorWithItsPositionSampleAndValue) {
  const FirstShotTable t = smallTable();
  const TableRows rows(t);
  ASSERT_EQ(rows.patches(), 3u);
  ASSERT_EQ(rows.factors(), 5u);
  std::vector<uint64_t> index;
  for (uint32_t j = 0; j < rows.patches(); ++j) {
    EXPECT_EQ(rows[j].first(), t.rowStart[j]);
    EXPECT_EQ(rows[j].size(), t.rowStart[j + 1] - t.rowStart[j]);
    for (const TableFactor f : rows[j]) {
      EXPECT_EQ(f.sample, t.sampleIndex[f.index]);
      EXPECT_EQ(f.r, t.factor[f.index]);
      const TableFactor same = rows.at(f.index);
      EXPECT_EQ(same.sample, f.sample);
      EXPECT_EQ(same.r, f.r);
      index.push_back(f.index);
    }
  }
  EXPECT_TRUE(rows[1].empty());
  EXPECT_EQ(index, (std::vector<uint64_t>{0, 1, 2, 3, 4}));
  uint64_t k = 0;
  for (const TableFactor f : rows.all()) EXPECT_EQ(f.index, k++);
  EXPECT_EQ(k, 5u);
  EXPECT_FALSE(rows.hasStoredVisible());
  FirstShotTable withVisible = smallTable();
  withVisible.visible = {1.0f, 0.5f, -1.0f, 0.0f, 1.0f};
  const TableRows visibleRows(withVisible);
  ASSERT_TRUE(visibleRows.hasStoredVisible());
  EXPECT_EQ(visibleRows.storedVisible(1), 0.5f);
  EXPECT_EQ(TableRows().patches(), 0u);
  EXPECT_EQ(TableRows().factors(), 0u);
}

TEST(TableRows, CheckNamesTheFirstFault) {
  EXPECT_EQ(TableRows::check(smallTable()), nullptr);
  FirstShotTable t = smallTable();
  t.rowStart.pop_back();
  ASSERT_NE(TableRows::check(t), nullptr);
  EXPECT_STREQ(TableRows::check(t), "table sizes do not match the patch count");
  t = smallTable();
  t.rowStart = {0, 3, 2, 5};
  EXPECT_STREQ(TableRows::check(t), "row starts are not increasing");
  t = smallTable();
  t.sampleIndex[3] = 2;
  EXPECT_STREQ(TableRows::check(t), "a factor refers to a light sample that does not exist");
}

TEST(TableRows, HashIsTheArraysBytes) {
  const FirstShotTable t = smallTable();
  Hasher a, b;
  TableRows::hash(t, a);
  b.bytes(t.rowStart.data(), t.rowStart.size() * sizeof(uint64_t));
  b.bytes(t.sampleIndex.data(), t.sampleIndex.size() * sizeof(uint32_t));
  b.bytes(t.factor.data(), t.factor.size() * sizeof(float));
  EXPECT_EQ(a.value(), b.value());
}
