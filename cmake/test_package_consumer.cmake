# Installs the project into a scratch prefix, then configures and builds a consumer that
# calls find_package(mlce) and links mlce::mlce, mlce::reader, mlce::spectrum and mlce::models.
set(prefix ${BINARY_DIR}/package-test/prefix)
set(consumer ${BINARY_DIR}/package-test/consumer)
file(REMOVE_RECURSE ${BINARY_DIR}/package-test)
file(MAKE_DIRECTORY ${consumer})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "install failed")
endif()
file(WRITE ${consumer}/CMakeLists.txt [=[
cmake_minimum_required(VERSION 3.25)
project(consumer CXX)
set(CMAKE_CXX_STANDARD 20)
find_package(mlce REQUIRED)
add_executable(consumer main.cpp)
target_link_libraries(consumer PRIVATE mlce::mlce mlce::reader mlce::spectrum mlce::models)
]=])
file(WRITE ${consumer}/main.cpp [=[
#include <mlce/mean_period.hpp>
#include <mlce/reader/format.hpp>
#include <mlce/models/dynamics.hpp>
#include <mlce/spectrum/floquet.hpp>
#include <cmath>
#include <cstdio>
int main() {
  mlce::Series s;
  s.dt = 0.01;
  s.channels.emplace_back();
  for (int i = 0; i < 1000; ++i) s.channels[0].push_back(std::sin(2 * M_PI * 5.0 * i * 0.01));
  auto r = mlce::estimate_mean_period(s, {});
  std::printf("%g\n", r.mean_frequency);
  if (mlce::reader::parse_channel_spec("rel:13:4:z").axis != 2) return 1;
  if (mlce::reader::default_registry().names().size() != 3) return 1;
  const auto scene = mlce::models::load_scene("", {"--rpm", "200"});
  const auto eig = mlce::spectrum::linear_eigen(mlce::models::time_invariant_form(scene).A);
  if (std::abs(eig.exponents(2) + 4067.5 / (2 * 1084.7)) > 1e-6) return 1;
  return std::abs(r.mean_frequency - 5.0) < 1e-6 ? 0 : 1;
}
]=])
execute_process(COMMAND ${CMAKE_COMMAND} -S ${consumer} -B ${consumer}/build -DCMAKE_PREFIX_PATH=${prefix}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "consumer configure failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${consumer}/build RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "consumer build failed")
endif()
execute_process(COMMAND ${consumer}/build/consumer RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "consumer run failed")
endif()
