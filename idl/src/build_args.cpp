#include "ispars/wire/build_args.hpp"

#include <array>
#include <bit>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

#include "ispars/params/fields.hpp"
#include "ispars/params/input_error.hpp"

namespace ispars::wire {
namespace {

using Slot = std::variant<double*, std::uint64_t*>;

// The message's member of each override, in RecipeOverrides' declaration order: bit i of
// `present` is the i-th.
std::array<Slot, 6> slots(msg::RecipeOverrides& m) {
  return {&m.dense_delta(),   &m.sparse_delta(),        &m.stretch(),
          &m.stretch_slack(), &m.stretch_slack_after(), &m.p_accept()};
}

// Calls f(member, slot, bit) for each declared override and its message member.
template <class Overrides, class F>
void each_override(Overrides& overrides, msg::RecipeOverrides& m, F&& f) {
  const std::array<Slot, 6> wire = slots(m);
  if (params::field_count<RecipeOverrides>() != wire.size())
    throw std::logic_error("an override without its wire member");
  std::uint32_t bit = 0;
  params::visit(overrides, [&](const auto&, auto& member) {
    using T = params::value_type_of<decltype(member)>;
    T* slot = std::get<T*>(wire[bit]);  // std::bad_variant_access: the types disagree (a test catches it)
    f(member, *slot, std::uint32_t{1} << bit);
    ++bit;
  });
}

}  // namespace

msg::BuildArgs to_message(const BuildRequest& request) {
  msg::BuildArgs b;
  b.method(std::string(to_string(request.method)));
  b.variant(request.variant ? std::string(to_string(*request.variant)) : std::string());
  b.samples(request.samples);
  b.seed(request.seed);
  b.replace(request.replace);
  msg::RecipeOverrides& m = b.overrides();
  m.present(0);
  each_override(request.overrides, m, [&](const auto& given, auto& slot, std::uint32_t bit) {
    if (!given) return;
    slot = *given;
    m.present(m.present() | bit);
  });
  return b;
}

BuildRequest from_message(const msg::BuildArgs& args, std::string_view file) {
  BuildRequest request;
  set_method(request, args.method().to_string(), args.variant().to_string(), file);
  request.samples = args.samples();
  request.seed = args.seed();
  request.replace = args.replace();
  msg::RecipeOverrides m = args.overrides();
  const std::uint32_t known = (std::uint32_t{1} << params::field_count<RecipeOverrides>()) - 1;
  if ((m.present() & ~known) != 0) {
    throw params::InputError(std::string(file), "overrides",
                             "presence bit " + std::to_string(std::countr_zero(m.present() & ~known)) +
                                 " names an override this daemon does not know (" + params::names<RecipeOverrides>() +
                                 ")");
  }
  each_override(request.overrides, m, [&](auto& member, const auto& slot, std::uint32_t bit) {
    if ((m.present() & bit) != 0) member = slot;
  });
  return request;
}

}  // namespace ispars::wire
