"""The live explorer, a Panel app: ``panel serve app/`` serves this folder (``main.py`` is the
page, ``app_hooks.py`` the server's start; the server's own modules are in ``server/``, the page's
here), ``windpump serve`` finds it as the installed package
``windpump_app``, and the tests import it by that name (``from windpump_app.explorer import
Explorer``). Served, Bokeh runs the folder as a package of its own (its modules import each other
relatively), so a checkout serves its own app without installing it.
"""
