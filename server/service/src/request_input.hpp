#pragma once
// The input the service's request errors name: InputError(kRequest, field, problem) reads
// "request: FIELD: PROBLEM", the same in every operation.

namespace ispars::service {

inline constexpr const char* kRequest = "request";

}  // namespace ispars::service
