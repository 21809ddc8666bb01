/* The family store (nospd_family_store.h): the pair order puts each point's
   bonds to owned points j < i, then to owned j > i, then to ghosts, each
   group in its build order, with every bond kept once; a list whose owned
   pairs are not symmetric is found out; compaction drops exactly the
   broken bonds and leaves what a rebuild without them gives, groups
   included. */

#include "nospd_family_store.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <tuple>
#include <vector>

using namespace NOSPD;

namespace {
struct Bond {
  int j, slot;
  double w;
};
using Lists = std::vector<std::vector<Bond>>;

// random symmetric lists of n owned points with ghosts n..n+g-1; slot
// numbers distinct per point, weights distinct everywhere
Lists random_lists(int n, int g, unsigned seed, bool symmetric = true)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Lists l(n);
  double w = 1.0;
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n + g; j++) {
      if (u(rng) > 0.4) continue;
      l[i].push_back({j, 0, w += 1.0});
      if (j < n && (symmetric || u(rng) < 0.5)) l[j].push_back({i, 0, w += 1.0});
    }
  for (auto &pl : l) {    // a build order that is not sorted
    std::shuffle(pl.begin(), pl.end(), rng);
    for (size_t k = 0; k < pl.size(); k++) pl[k].slot = (int) k;
  }
  return l;
}

void build(FamilyStore &f, const Lists &l)
{
  int64_t nb = 0;
  for (auto &pl : l) nb += pl.size();
  f.reserve((int) l.size(), nb);
  for (size_t i = 0; i < l.size(); i++) {
    f.open((int) i);
    for (auto &b : l[i]) f.add(b.j, b.slot, b.w);
  }
  f.close((int) l.size());
}

std::vector<std::tuple<int, int, double>> bonds_of(const FamilyStore &f, int i, int from, int to)
{
  std::vector<std::tuple<int, int, double>> v;
  for (int b = from; b < to; b++) v.emplace_back(f.j[b], f.slot[b], f.w[b]);
  (void) i;
  return v;
}
}    // namespace

TEST(FamilyStore, PairOrderGroupsEveryBondOnceInBuildOrder)
{
  const int n = 40, g = 15;
  const Lists l = random_lists(n, g, 7);
  FamilyStore f;
  build(f, l);
  f.order_for_pairs();
  EXPECT_TRUE(f.symmetric());
  for (int i = 0; i < n; i++) {
    ASSERT_EQ(f.count(i), (int) l[i].size());
    // the expected groups: the build order filtered
    std::vector<std::tuple<int, int, double>> grp[3];
    for (auto &b : l[i]) grp[b.j >= n ? 2 : (b.j < i ? 0 : 1)].emplace_back(b.j, b.slot, b.w);
    EXPECT_EQ(bonds_of(f, i, f.first[i], f.pair[i]), grp[0]) << i;
    EXPECT_EQ(bonds_of(f, i, f.pair[i], f.ghost[i]), grp[1]) << i;
    EXPECT_EQ(bonds_of(f, i, f.ghost[i], f.first[i + 1]), grp[2]) << i;
  }
}

TEST(FamilyStore, AsymmetricOwnedPairsAreFoundOut)
{
  const int n = 30, g = 5;
  FamilyStore f;
  build(f, random_lists(n, g, 11, false));
  f.order_for_pairs();
  EXPECT_FALSE(f.symmetric());
  // one bond i-j (j > i) dropped at j only: no longer symmetric
  Lists l = random_lists(n, g, 12);
  build(f, l);
  f.order_for_pairs();
  ASSERT_TRUE(f.symmetric());
  int i0 = -1, s0 = -1;
  for (int i = 0; i < n && i0 < 0; i++)
    for (auto &b : l[i])
      if (b.j < i) {
        i0 = i;
        s0 = b.slot;
        break;
      }
  ASSERT_GE(i0, 0);
  f.compact([&](int i, int slot) { return i == i0 && slot == s0; });
  EXPECT_FALSE(f.symmetric());
}

TEST(FamilyStore, CompactionEqualsARebuildWithoutTheBrokenBonds)
{
  const int n = 50, g = 20;
  Lists l = random_lists(n, g, 3);
  for (bool paired : {false, true}) {
    FamilyStore f;
    build(f, l);
    if (paired) f.order_for_pairs();
    // break a third of the bonds, at both ends where both are owned
    std::set<std::pair<int, int>> broken;    // (i, slot)
    std::mt19937 rng(5);
    for (int i = 0; i < n; i++)
      for (auto &b : l[i])
        if (b.j > i && rng() % 3 == 0) {
          broken.insert({i, b.slot});
          if (b.j < n)
            for (auto &c : l[b.j])
              if (c.j == i) broken.insert({b.j, c.slot});
        }
    const int v = f.version;
    f.compact([&](int i, int slot) { return broken.count({i, slot}) > 0; });
    EXPECT_NE(f.version, v);

    Lists kept(n);
    for (int i = 0; i < n; i++)
      for (auto &b : l[i])
        if (!broken.count({i, b.slot})) kept[i].push_back(b);
    FamilyStore r;
    build(r, kept);
    if (paired) r.order_for_pairs();
    EXPECT_EQ(f.symmetric(), paired);
    for (int i = 0; i < n; i++) {
      ASSERT_EQ(f.first[i], r.first[i]) << i;
      if (paired) {
        EXPECT_EQ(f.pair[i], r.pair[i]) << i;
        EXPECT_EQ(f.ghost[i], r.ghost[i]) << i;
      }
    }
    ASSERT_EQ(f.first[n], r.first[n]);
    for (int b = 0; b < r.first[n]; b++) {
      EXPECT_EQ(f.j[b], r.j[b]) << b;
      EXPECT_EQ(f.slot[b], r.slot[b]) << b;
      EXPECT_EQ(f.w[b], r.w[b]) << b;
    }
  }
}
