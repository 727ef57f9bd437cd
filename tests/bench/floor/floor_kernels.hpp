// The strongest hand-written kernels for the md velocity update
//
//   v_i += c * sum_{0 < |dx| < rc} -exp(-|dx|) dx / |dx|   (2D periodic unit square)
//
// copied from the project's shared/floor (floor.cpp and floor_step.cpp, the
// owner's hand-vectorised reference kernels) and trimmed to what bench_md and
// floor_step use: the cell grid with its halo ring, the AVX2 compaction kernel
// (compact_simd: a full sum per particle) and the SELL-4 neighbour list with
// its kernel (sell4: pure pair arithmetic, the floor). Their arithmetic is kept
// verbatim (the hand-written exp polynomial, the order of every sum, the
// masks), so that the reference stays the reference: a faster partc should
// come from partc, not from a weaker yardstick. As there, each kernel sums
// S_i = sum exp(-r)/r dx and then does v_i -= c S_i.
//
// floor_kernels.cpp needs AVX2 and is compiled with the floor's flags
// (-O3 -march=native -fno-math-errno -fopenmp-simd); this header needs
// nothing, so that code built with the project's flags can include it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace floor_ref {

// Particles counting-sorted by cell (cells floor(1/rc) to a side, at least rc
// wide), and the periodic images stored once in a ring of halo cells around
// the grid, so that each of the 3 neighbour rows of a cell is one contiguous
// range of the padded arrays px, py.
struct CellGrid {
  int n = 0, nc = 0, np = 0;
  double rc = 0;
  std::vector<int> perm;       // sorted index -> original index
  std::vector<int> cstart;     // interior cells, row-major (cy*nc+cx), size nc*nc+1
  std::vector<int> pstart;     // padded (halo) cells, row-major, size np*np+1
  std::vector<double> px, py;  // padded positions (+ kPad dummies at the end)
  std::vector<double> sx, sy;  // interior sorted positions
  static constexpr int kPad = 8;

  // False when floor(1/rc) < 3: the 3x3 stencil would visit a cell twice.
  bool build(int n, const double* x, const double* y, double rc);
};

// compact_simd's buffer of packed neighbours, one particle's worth.
struct CompactScratch {
  std::vector<double> bx, by, br2;
  // Room for the longest 3-row candidate range of g, plus a vector's padding.
  void fit(const CellGrid& g);
};

// compact_simd: per 4 candidates a permutation table packs the real
// neighbours, then full-vector arithmetic on the packed buffer. vx, vy in
// sorted order; s fitted to g.
void eval_compact_simd(const CellGrid& g, CompactScratch& s, double c, double* vx, double* vy);

// SELL-4 neighbour list: groups of 4 consecutive (sorted) i, lane l of slot s
// at base[g] + 4*s + l, each group padded to its longest list with
// (dx, dy) = (0, 0) entries that are masked out.
struct Sell4 {
  std::vector<std::int64_t> base;  // size ngroups+1
  std::vector<double> dx, dy;
  int n = 0;
  std::int64_t pairs = 0;  // real entries, without the padding
};

// Through a CSR list of (dx, dy) per pair, dropped once packed.
void build_sell4(const CellGrid& g, Sell4& s);
void eval_sell4(const Sell4& s, double c, double* vx, double* vy);

// The kernels above on one set of positions, for bench_md: they own their
// structures and velocities (v = 0 at the start, in sorted order inside),
// built here and not in the timed updates, as the floor measures them.
class VelocityUpdate {
 public:
  static bool applicable(double rc);
  // The floor's memory guard for neighbour lists (floor.cpp's
  // nlist_max_pairs): about 32 bytes a pair while the SELL-4 list is built.
  static constexpr double sell4_max_pairs = 3.5e8;
  static bool sell4_fits(int n, double rc);

  // Requires applicable(rc); the SELL-4 list only with_sell4.
  VelocityUpdate(const double* x, const double* y, int n, double rc, double c, bool with_sell4);

  void update_compact();
  void update_sell4();

  // In the order of the input positions.
  std::vector<std::array<double, 2>> velocities_compact() const;
  std::vector<std::array<double, 2>> velocities_sell4() const;

 private:
  std::vector<std::array<double, 2>> in_input_order(const std::vector<double>& vx,
                                                    const std::vector<double>& vy) const;

  CellGrid grid_;
  CompactScratch scratch_;
  Sell4 sell4_;
  double c_;
  std::vector<double> compact_vx_, compact_vy_, sell4_vx_, sell4_vy_;  // sorted order
};

}  // namespace floor_ref
