"""``pdamper explore``: a local web page to design a damper by hand (docs/explore.md).

:mod:`pdamper.explore.design` holds the page's inputs and computes its views without a
browser; :mod:`pdamper.explore.app` lays them out as a Panel application (the optional
``explore`` dependencies: ``pip install -e ".[explore]"``).
"""
