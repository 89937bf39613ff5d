// The packed declaration of a distribution mode
// (virtual_actuators.distribution.partitioned.compiled), read as views.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace va {

// Columns of the per-chain header: velocity columns, own constrained joints, ball axes, rank,
// natural rows, free entries, start of its free entries.
constexpr std::int64_t K_COLS = 0, C_CON = 1, NB_BALL = 2, RANK = 3, L_ROWS = 4, D_FREE = 5,
                       START = 6, HEADER = 7;
// Entries of the packed integer header.
constexpr std::int64_t PACK_HEADER = 9;

struct Packed {
  std::int64_t mode = 0, n = 0, p = 0, width = 0, s1 = 0, m = 0, K = 0, nv_springs = 0, s0 = 0;
  const std::int64_t *keep = nullptr, *axis_rows = nullptr, *frame_rows = nullptr,
                     *chain_ints = nullptr, *torque_rows = nullptr, *plan = nullptr,
                     *layout = nullptr;
  const double *chain_signs = nullptr, *springs = nullptr, *const_rows = nullptr,
               *const_rhs = nullptr, *torque_signs = nullptr;

  Packed() = default;
  // Views of ints and floats (which must outlive this object); no check.
  Packed(const std::int64_t* i, const double* f) {
    mode = i[0];
    n = i[1];
    p = i[2];
    width = i[3];
    s1 = i[4];
    m = i[5];
    K = i[6];
    nv_springs = i[7];
    s0 = i[8];
    std::int64_t at = PACK_HEADER;
    keep = i + at;
    at += n;
    axis_rows = i + at;
    at += n;
    frame_rows = i + at;
    at += 2 + p;
    chain_ints = i + at;
    at += p * width;
    torque_rows = i + at;
    at += 3 * s1;
    plan = i + at;
    layout = i + at + m;
    chain_signs = f;
    std::int64_t af = p * K;
    springs = f + af;
    af += 5 * nv_springs;
    const_rows = f + af;
    af += s0 * p * n;
    const_rhs = f + af;
    torque_signs = f + af + s0;
  }

  // Views after checking the sizes and every index the kernel follows (std::invalid_argument).
  static Packed checked(const std::vector<std::int64_t>& ints, const std::vector<double>& floats,
                        std::int64_t nv) {
    auto require = [](bool ok, const char* what) {
      if (!ok) throw std::invalid_argument(what);
    };
    const auto ni = static_cast<std::int64_t>(ints.size());
    require(ni >= PACK_HEADER, "packed ints: no header");
    for (std::int64_t k = 0; k < PACK_HEADER; ++k) require(ints[k] >= 0, "packed ints: header");
    const std::int64_t n = ints[1], p = ints[2], width = ints[3], s1 = ints[4], m = ints[5];
    require(ints[0] <= 1 && n >= 1 && n <= 6 && p >= 1, "packed ints: mode, n or p");
    require(ni == PACK_HEADER + 2 * n + 2 + p + p * width + 3 * s1 + m + 4,
            "packed ints: wrong length");
    Packed P(ints.data(), floats.data());
    require(static_cast<std::int64_t>(floats.size()) ==
                P.p * P.K + 5 * P.nv_springs + P.s0 * P.p * P.n + P.s0 + 2 * P.p * P.s1,
            "packed floats: wrong length");
    require(P.nv_springs == nv, "packed tables: the springs table must have nv rows");
    const std::int64_t* L = P.layout;
    require(L[0] == P.K && L[0] >= 0 && L[1] >= 0 && L[2] >= 0 && L[3] >= 0 &&
                width == HEADER + L[0] + L[1] + 3 + L[2] + L[3],
            "packed tables: layout");
    for (std::int64_t a = 0; a < n; ++a)
      require(P.axis_rows[a] >= 0 && P.axis_rows[a] < 6, "packed tables: axis rows");
    for (std::int64_t r = 0; r < 2 + p; ++r)
      require(P.frame_rows[r] >= 0, "packed tables: frame rows");
    const std::int64_t rows_width = std::max<std::int64_t>(L[2], 1);
    const std::int64_t con_start = HEADER + L[0], ball_start = con_start + L[1];
    const std::int64_t cfs_start = ball_start + 3, free_start = cfs_start + L[2];
    for (std::int64_t i = 0; i < p; ++i) {
      const std::int64_t* row = P.chain_ints + i * width;
      const std::int64_t k_i = row[K_COLS], c_i = row[C_CON], nb = row[NB_BALL];
      const std::int64_t rank = row[RANK], l_i = row[L_ROWS], d_i = row[D_FREE];
      require(k_i >= 0 && k_i <= L[0] && c_i >= 0 && c_i <= L[1] && c_i <= k_i && nb >= 0 &&
                  nb <= 3 && l_i >= 0 && l_i <= L[2] && d_i >= 0 && d_i <= L[3],
              "packed tables: chain header");
      require(rank >= 0 && rank <= n && rank <= k_i + nb && c_i + nb + n - rank <= rows_width,
              "packed tables: chain rank");
      for (std::int64_t j = 0; j < k_i; ++j)
        require(row[HEADER + j] >= 0 && row[HEADER + j] < nv, "packed tables: chain columns");
      for (std::int64_t j = 0; j < c_i; ++j)
        require(row[con_start + j] >= 0 && row[con_start + j] < k_i,
                "packed tables: constrained joints");
      for (std::int64_t j = 0; j < nb; ++j)
        require(row[ball_start + j] >= 0 && row[ball_start + j] < 3, "packed tables: ball axes");
      for (std::int64_t j = 0; j < l_i; ++j)
        require(row[cfs_start + j] >= 0 && row[cfs_start + j] < n, "packed tables: CFS");
      for (std::int64_t j = 0; j < d_i; ++j)
        require(row[free_start + j] >= 0 && row[free_start + j] < n, "packed tables: free entries");
      if (P.mode == 1)
        require(row[START] >= 0 && row[START] + d_i <= m && l_i <= rows_width,
                "packed tables: free entries' start");
    }
    for (std::int64_t t = 0; t < s1; ++t) {
      const std::int64_t* row = P.torque_rows + 3 * t;
      require(
          row[0] >= 0 && row[0] < nv && row[1] >= -1 && row[1] < nv && row[2] >= 0 && row[2] <= 1,
          "packed tables: torque rows");
    }
    for (std::int64_t e = 0; e < m; ++e)
      require(P.plan[e] >= 0 && P.plan[e] < m, "packed tables: plan");
    require(P.mode == 0 || m >= P.s0 + s1, "packed tables: plan shorter than the hard rows");
    for (std::int64_t v = 0; v < nv; ++v)
      require(P.springs[5 * v + 2] < 0 || P.springs[5 * v + 2] >= 0,
              "packed tables: springs");  // not NaN
    return P;
  }

  std::int64_t chain(std::int64_t i, std::int64_t column) const {
    return chain_ints[i * width + column];
  }
  const std::int64_t* chain_row(std::int64_t i) const { return chain_ints + i * width; }
  // Length of the tick's output buffer: forces, tau, passive, produced, requested.
  std::int64_t out_size(std::int64_t nv) const { return p * n + 2 * nv + 2 * n; }
  std::int64_t max_frame_row() const { return *std::max_element(frame_rows, frame_rows + 2 + p); }
  // Largest index of q the springs read (-1: none).
  std::int64_t max_q_index() const {
    std::int64_t top = -1;
    for (std::int64_t v = 0; v < nv_springs; ++v) {
      const double* sp = springs + 5 * v;
      if (sp[2] >= 0) top = std::max(top, static_cast<std::int64_t>(sp[2]) + (sp[3] > 0 ? 1 : 0));
    }
    return top;
  }
};

}  // namespace va
