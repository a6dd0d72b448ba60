"""One router per resource noun.

Every module here that defines ``router: fastapi.APIRouter`` is included by
``motionsim.api.main.create_app`` automatically — adding a resource touches no shared list.
"""
