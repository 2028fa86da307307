# Inertia unit tests (server/physics/inertia.cpp). Included from tests/physics/CMakeLists.txt:
#   include(${CMAKE_CURRENT_LIST_DIR}/inertia_tests.cmake)
add_executable(inertia_test ${CMAKE_CURRENT_LIST_DIR}/inertia_test.cpp)
target_link_libraries(inertia_test PRIVATE rigid_physics GTest::gtest_main)
gtest_discover_tests(inertia_test)
