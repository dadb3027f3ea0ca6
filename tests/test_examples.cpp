// placeholder while the stage is written
#include <gtest/gtest.h>
