// stub: implemented by its stage owner
