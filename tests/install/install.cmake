# cmc installed as users install it, then used from outside the checkout
# (tests/install/install_test.py says what each checks). Label 'install' (pip_fresh, a whole
# build inside pip, 'slow'); each works in BUILD/install-tests/<test>.
foreach(test prefix pip_target pip_venv pip_fresh)
  add_test(NAME install.${test}
           COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/tests/install/install_test.py ${test} ${CMAKE_SOURCE_DIR}
                   ${CMAKE_BINARY_DIR} ${CMAKE_BINARY_DIR}/install-tests/${test})
  set_tests_properties(install.${test} PROPERTIES LABELS "install;python" RESOURCE_LOCK cmc_pip_build TIMEOUT 1500)
endforeach()
set_tests_properties(install.pip_fresh PROPERTIES LABELS "install;python;slow")
