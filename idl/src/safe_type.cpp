#include "ispars/wire/safe_type.hpp"

#include <fastdds/dds/log/Log.hpp>

#include <string>

namespace ispars::wire {

void report_malformed_sample(const char* type_name, const char* what) {
  namespace fdds = eprosima::fastdds::dds;
  fdds::Log::QueueLog(std::string("dropped a malformed ") + type_name + " sample: " + what,
                      fdds::Log::Context{__FILE__, __LINE__, __func__, "ISPARS"}, fdds::Log::Kind::Warning);
}

}  // namespace ispars::wire
