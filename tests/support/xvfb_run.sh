#!/bin/sh
# Runs a test program under a private X server, Xvfb, with Mesa's software OpenGL (llvmpipe), so
# that the viewer's tests need neither a screen nor a GPU. Listing the tests needs no server.
case " $* " in
*" --list-test-cases "* | *" --list-test-suites "*) exec "$@" ;;
esac
LIBGL_ALWAYS_SOFTWARE=1 exec xvfb-run -a -s "-screen 0 1280x1024x24 -nolisten tcp" "$@"
