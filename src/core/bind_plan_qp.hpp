// A compiled machine's QP attachment (bind_plan.cpp): the QP distribution's compiled step on the
// last certified active set (QP::again_raw, bind_qp.hpp), on the Python distribution's own
// workspace and warm start. A tick whose active set changed, or before the first certified
// answer, is the attachment's Python piece (DAQP, ProxQP), which hands the new warm start back.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "bind_common.hpp"
#include "bind_qp.hpp"
#include "plan_machine.hpp"

namespace va::py {

class QPSolver : public va::plan::Solver {
 public:
  // The QP (kept alive by the binding), this thread's workspace (buffer, layout, kept: kept
  // alive by the caller), the prescribed axes (0/1), their weights, the tolerances (active,
  // exact, accuracy) and a configuration to check the workspace against.
  QPSolver(const QP& qp, const F1& q, MF1 buffer, const I1& layout, const I1& kept, const I1& keep,
           const F1& weights, const F1& tolerances, std::int64_t nv)
      : qp_(&qp), nv_(nv) {
    require(len(keep) == qp.n() && length(weights) >= len(kept), "keep (n,), weights (k,)");
    require(length(tolerances) == 3, "tolerances: active, exact, accuracy");
    std::vector<double> zeros(static_cast<std::size_t>(qp.n()), 0.0);
    const F1 wrench(zeros.data(), {static_cast<std::size_t>(qp.n())});
    views_ = std::make_shared<va::QPViews>(qp.views(q, wrench, kept, buffer, layout));
    buffer_ = buffer.data();
    buffer_size_ = length(buffer);
    layout_ = copy<std::int64_t>(layout);
    kept_ = copy<std::int64_t>(kept);
    keep_ = copy<std::int64_t>(keep);
    weights_ = copy<double>(weights);
    std::copy(tolerances.data(), tolerances.data() + 3, tolerances_);
    out_.resize(static_cast<std::size_t>(qp.chains() * qp.n() + 2 * nv + 2 * qp.n()));
    active_.resize(static_cast<std::size_t>(views_->m_in));
  }

  // The warm start: the multipliers of the last certified answer (kept alive by the caller,
  // updated in place), or none (the Python piece solves from cold).
  void set_guess(std::optional<MF1> guess) {
    if (!guess) {
      guess_ = nullptr;
      return;
    }
    require(length(*guess) == views_->m_in, "guess must be (m,)");
    guess_ = guess->data();
  }

  bool solve(const double* jw, const double* frames, const double* q, const double* wrench,
             double* tau, double* produced) override {
    count_ = -1;
    if (guess_ == nullptr) return false;
    saved_.assign(guess_, guess_ + views_->m_in);  // put back if the tick is handed on
    std::fill(out_.begin(), out_.end(), 0.0);
    count_ =
        qp_->again_raw(jw, frames, q, wrench, kept_.data(), static_cast<std::int64_t>(kept_.size()),
                       *views_, buffer_, buffer_size_, layout_.data(), keep_.data(),
                       weights_.data(), guess_, tolerances_[0], tolerances_[1], tolerances_[2],
                       out_.data(), active_.data(), z_, multipliers_, solved_);
    if (count_ < 0) {
      std::copy(saved_.begin(), saved_.end(), guess_);
      return false;
    }
    const std::int64_t pn = qp_->chains() * qp_->n();
    std::copy(out_.data() + pn, out_.data() + pn + nv_, tau);
    std::copy(out_.data() + pn + 2 * nv_, out_.data() + pn + 2 * nv_ + qp_->n(), produced);
    return true;
  }

  // The last tick's answer: (count, (residual, scale, rounding)), -1 when the core did not solve.
  nb::tuple answer() const {
    return nb::make_tuple(count_,
                          nb::make_tuple(solved_.residual, solved_.scale, solved_.rounding));
  }
  std::vector<double>& out() { return out_; }
  std::vector<std::int64_t>& active() { return active_; }

 private:
  const QP* qp_;
  std::int64_t nv_;
  std::shared_ptr<va::QPViews> views_;
  double* buffer_ = nullptr;
  std::int64_t buffer_size_ = 0;
  std::vector<std::int64_t> layout_, kept_, keep_;
  std::vector<double> weights_;
  double tolerances_[3] = {0.0, 0.0, 0.0};
  double* guess_ = nullptr;
  std::vector<double> saved_, out_, z_, multipliers_;
  std::vector<std::int64_t> active_;
  va::Distributed solved_{};
  std::int64_t count_ = -1;
};

}  // namespace va::py
