// A torque of any type (the interface of model/torque.hpp) behind one type: the kind of
// varying_torque (runs/varying_torque.hpp) that lets a torque type of the user's own run in the
// compiled run drivers instead of instantiating drivers of its own (docs/design.md, "The compiled
// kernels"). The evaluation is the type's own, called through one virtual function, so a run
// gives the same doubles as the type would in drivers compiled for it.
//
// It has value semantics: a copy copies the torque, as the runs copy their problem (a torque may
// keep scratch space and a pinned interval, and sweep and map run copies on several threads).
#pragma once

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/torque.hpp>

#include <array>
#include <concepts>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace eulervop::detail {

template <class T>
class erased_torque {
 public:
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = true;

  template <class G>
  explicit erased_torque(G g) : self_(std::make_unique<holder<G>>(std::move(g))) {}
  erased_torque(const erased_torque& other) : self_(other.self_->clone()) {}
  erased_torque& operator=(const erased_torque& other) {
    if (this != &other) self_ = other.self_->clone();
    return *this;
  }
  erased_torque(erased_torque&&) noexcept = default;
  erased_torque& operator=(erased_torque&&) noexcept = default;
  ~erased_torque() = default;

  // A torque that reads the attitude (it has set_attitude): its runs must carry q.
  bool reads_attitude() const { return self_->reads_attitude(); }
  void set_attitude(const quaternion<T>& q) const { self_->set_attitude(q); }

  vec3<T> value(const T& t, const vec3<T>& y) const { return self_->value(t, y); }
  void add_jacobian(const T& t, const vec3<T>& y, std::array<vec3<T>, 3>& J) const { self_->add_jacobian(t, y, J); }

  // A torque without breakpoints has none, one interval, and nothing to pin.
  const std::vector<T>& breakpoints() const { return self_->breakpoints(); }
  std::size_t interval_at(const T& t) const { return self_->interval_at(t); }
  void pin(std::size_t interval) const { self_->pin(interval); }
  void unpin() const { self_->unpin(); }

 private:
  struct base {
    virtual ~base() = default;
    virtual std::unique_ptr<base> clone() const = 0;
    virtual bool reads_attitude() const = 0;
    virtual void set_attitude(const quaternion<T>& q) const = 0;
    virtual vec3<T> value(const T& t, const vec3<T>& y) const = 0;
    virtual void add_jacobian(const T& t, const vec3<T>& y, std::array<vec3<T>, 3>& J) const = 0;
    virtual const std::vector<T>& breakpoints() const = 0;
    virtual std::size_t interval_at(const T& t) const = 0;
    virtual void pin(std::size_t interval) const = 0;
    virtual void unpin() const = 0;
  };

  template <class G>
  struct holder final : base {
    static constexpr bool piecewise = piecewise_torque<G>;
    static constexpr bool staged = requires(const G& g, const quaternion<T>& q) { g.set_attitude(q); };

    explicit holder(G g) : g_(std::move(g)) {}
    std::unique_ptr<base> clone() const override { return std::make_unique<holder>(g_); }
    bool reads_attitude() const override { return staged; }
    void set_attitude(const quaternion<T>& q) const override {
      if constexpr (staged) g_.set_attitude(q);
    }
    vec3<T> value(const T& t, const vec3<T>& y) const override { return g_.value(t, y); }
    void add_jacobian(const T& t, const vec3<T>& y, std::array<vec3<T>, 3>& J) const override {
      if constexpr (G::depends_on_state) g_.add_jacobian(t, y, J);
    }
    const std::vector<T>& breakpoints() const override {
      if constexpr (piecewise) return g_.breakpoints();
      else return none_;
    }
    std::size_t interval_at(const T& t) const override {
      if constexpr (piecewise) return g_.interval_at(t);
      else return 0;
    }
    void pin(std::size_t interval) const override {
      if constexpr (piecewise) g_.pin(interval);
    }
    void unpin() const override {
      if constexpr (piecewise) g_.unpin();
    }

    G g_;
    std::vector<T> none_;
  };

  std::unique_ptr<base> self_;
};

// The runs are in double only: the torque converts to its own type.
template <class U, class T>
  requires std::same_as<U, T>
erased_torque<U> convert_torque(const erased_torque<T>& g) {
  return g;
}

}  // namespace eulervop::detail
